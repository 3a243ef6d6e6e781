# QualMesh FEM mesher for FreeCAD: the GUI command, as FEM's femcommands/commands.py (_MeshGmshFromShape).
#
# QualMesh_MeshFromShape adds a QualMesh mesh object for the selected shape (into the active analysis, if any) and
# opens its task panel. Every document change goes through FreeCADGui.doCommand, so a macro records it.
# Importing this module registers the command; the FEM workbench's injected toolbar imports it by name.

import FreeCAD
import FreeCADGui

from . import view_mesh_qualmesh

COMMAND_NAME = "QualMesh_MeshFromShape"


def _selected_shape_object():
    selection = FreeCADGui.Selection.getSelection()
    if len(selection) != 1:
        return None
    obj = selection[0]
    if hasattr(obj, "Shape") and not obj.isDerivedFrom("Fem::FemMeshObject") and obj.Shape.Solids:
        return obj
    return None


class _MeshQualMeshFromShape(object):
    """The QualMesh_MeshFromShape command definition."""

    def GetResources(self):
        return {"Pixmap": view_mesh_qualmesh.icon_path(),
                "MenuText": "FEM mesh from shape by QualMesh",
                "ToolTip": "Create a FEM mesh (quality tetrahedra, 2nd order on the CAD faces) from the selected "
                           "solid by the QualMesh mesher"}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None and _selected_shape_object() is not None

    def Activated(self):
        part = _selected_shape_object()
        if part is None:
            return
        FreeCAD.ActiveDocument.openTransaction("Create FEM mesh by QualMesh")
        FreeCADGui.addModule("qualmesh_fem")
        FreeCADGui.doCommand("qualmesh_fem.make_mesh_qualmesh(FreeCAD.ActiveDocument, 'FEMMeshQualMesh')")
        FreeCADGui.doCommand("FreeCAD.ActiveDocument.ActiveObject.Part = FreeCAD.ActiveDocument.{}"
                             .format(part.Name))
        try:
            import FemGui
            analysis = FemGui.getActiveAnalysis()
        except ImportError:
            analysis = None
        if analysis is not None and analysis.Document == FreeCAD.ActiveDocument:
            FreeCADGui.addModule("FemGui")
            FreeCADGui.doCommand("FemGui.getActiveAnalysis().addObject(FreeCAD.ActiveDocument.ActiveObject)")
        FreeCAD.ActiveDocument.commitTransaction()
        FreeCADGui.doCommand("FreeCADGui.ActiveDocument.setEdit(FreeCAD.ActiveDocument.ActiveObject.Name)")
        FreeCADGui.Selection.clearSelection()


def register():
    if COMMAND_NAME not in FreeCADGui.listCommands():
        FreeCADGui.addCommand(COMMAND_NAME, _MeshQualMeshFromShape())


register()
