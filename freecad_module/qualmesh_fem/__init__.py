# QualMesh FEM mesher for FreeCAD: the headless API (FreeCADCmd scripts and the GUI alike).
#
#   import qualmesh_fem
#   femmesh = qualmesh_fem.mesh_shape(shape, max_size=8, order=2)          # a Fem.FemMesh with groups
#   mesh_obj = qualmesh_fem.make_mesh_qualmesh(doc, "FEMMeshQualMesh")     # the mesh object, empty
#   mesh_obj = qualmesh_fem.add_mesh_to_analysis(analysis, part_obj, max_size=8)   # object, meshed, in the analysis
#
# The mesh has the groups Solid<i> (Volume), Face<i> (Face and Node: every node of the CAD face, mid nodes
# included) and Edge<i> (Node), named as FreeCAD names the entities of the shape. Nothing here imports the GUI.

from .qualmeshtools import (MeshParameters, MeshRunResult, MeshRunStatus, QualMeshCancelled, QualMeshError,
                            QualMeshRun, QualMeshTools, find_qualmesh, mesh_shape)

__all__ = ["mesh_shape", "make_mesh_qualmesh", "add_mesh_to_analysis", "QualMeshTools", "QualMeshError",
           "QualMeshCancelled", "MeshRunResult", "MeshRunStatus", "MeshParameters", "QualMeshRun", "find_qualmesh",
           "group_elements"]


def make_mesh_qualmesh(doc, name="FEMMeshQualMesh"):
    """Add an (empty) QualMesh mesh object to `doc`, with its view provider when the GUI is up."""
    import FreeCAD
    from . import mesh_qualmesh
    obj = doc.addObject("Fem::FemMeshObjectPython", name)
    mesh_qualmesh.MeshQualMesh(obj)
    if FreeCAD.GuiUp:
        from . import view_mesh_qualmesh
        view_mesh_qualmesh.VPMeshQualMesh(obj.ViewObject)
    return obj


def add_mesh_to_analysis(analysis, part_obj, max_size=0.0, order=2, name="FEMMeshQualMesh", create=True,
                         log=None, **properties):
    """Add a QualMesh mesh object of `part_obj` to `analysis` and, with create=True, mesh it.

    max_size in model units (0 = automatic); order 1 or 2; further properties by name (RadiusEdgeBound=1.8,
    SliverAngle=12, Pumping=False, CharacteristicLengthMin=...). Raises QualMeshError when meshing fails; the
    object then stays in the analysis without a mesh. Returns the mesh object.
    """
    obj = make_mesh_qualmesh(analysis.Document, name)
    obj.Part = part_obj
    obj.CharacteristicLengthMax = float(max_size)
    obj.ElementOrder = "1st" if int(order) == 1 else "2nd"
    for key, value in properties.items():
        setattr(obj, key, value)
    analysis.addObject(obj)
    if create:
        result = QualMeshTools(obj, analysis).create_mesh(log=log)
        if not result.succeeded:
            raise QualMeshError(result.message)
    return obj


def group_elements(femmesh, name, element_type):
    """Ids of the group `name` of type element_type ("Node", "Face", "Volume") in a Fem.FemMesh, or None."""
    for group in femmesh.Groups:
        if femmesh.getGroupName(group) == name and femmesh.getGroupElementType(group) == element_type:
            return femmesh.getGroupElements(group)
    return None
