# QualMesh FEM mesher for FreeCAD: the view provider of the mesh object, as FEM's femviewprovider/view_mesh_gmsh.py.
#
# Double click or Edit opens the task panel; mesh regions are shown as children. A document saved headless stores
# no view-provider proxy: MeshQualMesh.onDocumentRestored attaches this one again when the GUI is up.

import os

import FreeCAD
import FreeCADGui

ICON_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "Resources", "icons")


def icon_path(name="QualMesh_MeshFromShape.svg"):
    return os.path.join(ICON_DIR, name)


class VPMeshQualMesh(object):
    """View provider proxy of a QualMesh mesh object."""

    def __init__(self, vobj):
        vobj.Proxy = self
        self.attach(vobj)

    def getIcon(self):
        return icon_path()

    def attach(self, vobj):
        self.ViewObject = vobj
        self.Object = vobj.Object

    def updateData(self, obj, prop):
        return

    def onChanged(self, vobj, prop):
        return

    def setEdit(self, vobj, mode=0):
        from . import task_mesh_qualmesh
        # show the mesh being edited, hide the other meshes (as FEM's mesh panels do)
        for o in vobj.Object.Document.Objects:
            if o.isDerivedFrom("Fem::FemMeshObject") and o != vobj.Object and o.ViewObject is not None:
                o.ViewObject.hide()
        vobj.show()
        FreeCADGui.Control.showDialog(task_mesh_qualmesh._TaskPanel(vobj.Object))
        return True

    def unsetEdit(self, vobj, mode=0):
        FreeCADGui.Control.closeDialog()
        return True

    def doubleClicked(self, vobj):
        guidoc = FreeCADGui.getDocument(vobj.Object.Document)
        if guidoc.getInEdit():
            message = "Active Task Dialog found! Please close this one before opening a new one!"
            FreeCAD.Console.PrintError(message + "\n")
            return True
        _activate_analysis_of(vobj.Object)
        guidoc.setEdit(vobj.Object.Name)
        return True

    def claimChildren(self):
        return list(getattr(self.Object, "MeshRegionList", []) or [])

    def canDragObjects(self):
        return True

    def canDropObjects(self):
        return True

    def canDragObject(self, dragged_object):
        return getattr(getattr(dragged_object, "Proxy", None), "Type", "") == "Fem::MeshRegion"

    def canDropObject(self, incoming_object):
        return getattr(getattr(incoming_object, "Proxy", None), "Type", "") == "Fem::MeshRegion"

    def dragObject(self, selfvp, dragged_object):
        regions = self.Object.MeshRegionList
        if dragged_object in regions:
            regions.remove(dragged_object)
            self.Object.MeshRegionList = regions

    def dropObject(self, selfvp, incoming_object):
        regions = self.Object.MeshRegionList
        regions.append(incoming_object)
        self.Object.MeshRegionList = regions

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None


def _activate_analysis_of(obj):
    """Make the analysis that holds obj the active one (FEM's mesh panels mesh for the active analysis)."""
    try:
        import FemGui
    except ImportError:
        return
    for o in obj.Document.Objects:
        if o.isDerivedFrom("Fem::FemAnalysis") and obj in o.Group:
            FemGui.setActiveAnalysis(o)
            return
