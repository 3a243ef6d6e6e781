# QualMesh FEM mesher for FreeCAD: runs at start-up in FreeCADCmd and in the GUI.
#
# Nothing to register headless: `import qualmesh_fem` gives the API (mesh_shape, make_mesh_qualmesh,
# add_mesh_to_analysis). The addon's folder is on sys.path because FreeCAD found it under Mod/.
