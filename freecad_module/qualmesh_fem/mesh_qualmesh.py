# QualMesh FEM mesher for FreeCAD: the mesh object (properties only), as FEM's femobjects/mesh_gmsh.py.
#
# A Fem::FemMeshObjectPython, so that an analysis and FEM's CalculiX writer take it as the analysis mesh. The
# result lives in FemMesh; meshing is explicit (task panel Apply, QualMeshTools.create_mesh()), never on recompute.
# Properties follow Gmsh's names where they mean the same (Part, CharacteristicLengthMax/Min, ElementOrder,
# MeshRegionList); RadiusEdgeBound, SliverAngle and Pumping are QualMesh's own; Nodes, Tetrahedra,
# MinDihedralAngle and TetsBelow10Deg are read-only statistics of the last successful run.

import FreeCAD

# addProperty's attribute bit for a property the property editor shows read-only (App::Prop_ReadOnly).
_PROP_READ_ONLY = 1


class MeshQualMesh(object):
    """Proxy of a QualMesh mesh object."""

    Type = "QualMesh::FemMeshQualMesh"
    known_element_orders = ["1st", "2nd"]
    statistics_properties = ("Nodes", "Tetrahedra", "MinDihedralAngle", "TetsBelow10Deg")

    def __init__(self, obj):
        obj.Proxy = self
        self.add_properties(obj)

    def onDocumentRestored(self, obj):
        # Adds properties a newer version introduced, and re-attaches the view provider when the document was
        # saved headless (no view-provider proxy is stored then) and is opened in the GUI.
        self.add_properties(obj)
        if FreeCAD.GuiUp:
            from . import view_mesh_qualmesh
            vobj = obj.ViewObject
            if vobj is not None and not isinstance(getattr(vobj, "Proxy", None), view_mesh_qualmesh.VPMeshQualMesh):
                view_mesh_qualmesh.VPMeshQualMesh(vobj)

    def execute(self, obj):
        # The mesh is made only on request (Apply, create_mesh()); a recompute keeps it.
        return

    def add_properties(self, obj):
        # Called from __init__ and onDocumentRestored: adds only what is missing.
        def add(type_name, name, group, doc, default, attributes=0):
            if not hasattr(obj, name):
                obj.addProperty(type_name, name, group, doc, attributes)
                setattr(obj, name, default)

        add("App::PropertyLinkList", "MeshRegionList", "Base",
            "Mesh regions of the mesh (local CharacteristicLength on faces, edges, solids)", [])
        add("App::PropertyLink", "Part", "FEM Mesh",
            "Geometry object the mesh is made from. The geometry object has to have a Shape.", None)
        add("App::PropertyLength", "CharacteristicLengthMax", "FEM QualMesh Params",
            "Max mesh element size, longest edge (0.0 = automatic)", 0.0)
        add("App::PropertyLength", "CharacteristicLengthMin", "FEM QualMesh Params",
            "Min mesh element size (0.0 = automatic; needs a qualmesh with --min-size)", 0.0)
        if not hasattr(obj, "ElementOrder"):
            obj.addProperty("App::PropertyEnumeration", "ElementOrder", "FEM QualMesh Params",
                            "Order of mesh elements (2nd: 10-node tetrahedra, mid nodes on curved faces)")
            obj.ElementOrder = MeshQualMesh.known_element_orders
            obj.ElementOrder = "2nd"
        add("App::PropertyFloat", "RadiusEdgeBound", "FEM QualMesh Params",
            "Radius-edge ratio bound rho0 of the refinement (>= 1.1; smaller: better shapes, more elements)", 2.0)
        add("App::PropertyAngle", "SliverAngle", "FEM QualMesh Params",
            "A tetrahedron with a smaller dihedral angle is a sliver that pumping removes (0 to 60 deg)", 15.0)
        add("App::PropertyBool", "Pumping", "FEM QualMesh Params",
            "Remove slivers by pumping vertex weights (off: plain Delaunay refinement)", True)
        add("App::PropertyInteger", "Nodes", "Mesh Statistics",
            "Nodes of the mesh (mid nodes included)", 0, _PROP_READ_ONLY)
        add("App::PropertyInteger", "Tetrahedra", "Mesh Statistics",
            "Tetrahedra of the mesh", 0, _PROP_READ_ONLY)
        add("App::PropertyAngle", "MinDihedralAngle", "Mesh Statistics",
            "Smallest dihedral angle of the straight-sided tetrahedra", 0.0, _PROP_READ_ONLY)
        add("App::PropertyInteger", "TetsBelow10Deg", "Mesh Statistics",
            "Tetrahedra with a dihedral angle below 10 degrees", 0, _PROP_READ_ONLY)
        for name in MeshQualMesh.statistics_properties:
            obj.setEditorMode(name, 1)

    # Nothing of the proxy is stored in the document: its state is the object's properties.
    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

