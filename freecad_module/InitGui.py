# QualMesh FEM mesher for FreeCAD: runs at GUI start-up.
#
# Adds the QualMesh workbench (its toolbar and menu hold QualMesh_MeshFromShape) and, once, a QualMesh toolbar in
# FEM's workbench through FreeCAD's custom-toolbar parameters (qualmesh_fem/femtoolbar.py).


class QualMeshWorkbench(Workbench):  # noqa: F821 (FreeCAD's InitGui namespace defines Workbench)
    "QualMesh: quality tetrahedral FEM meshes"

    def __init__(self):
        import qualmesh_fem.view_mesh_qualmesh as view
        self.__class__.Icon = view.icon_path("QualMeshWorkbench.svg")
        self.__class__.MenuText = "QualMesh"
        self.__class__.ToolTip = "QualMesh: quality tetrahedral meshes for FEM, beside Gmsh"

    def Initialize(self):
        import qualmesh_fem.commands
        self.appendToolbar("QualMesh", [qualmesh_fem.commands.COMMAND_NAME])
        self.appendMenu("&QualMesh", [qualmesh_fem.commands.COMMAND_NAME])

    def GetClassName(self):
        return "Gui::PythonWorkbench"


Gui.addWorkbench(QualMeshWorkbench())  # noqa: F821

try:
    import qualmesh_fem.femtoolbar
    qualmesh_fem.femtoolbar.install_fem_toolbar()
except Exception as e:  # a broken preference must not stop FreeCAD from starting
    App.Console.PrintError("QualMesh: could not add the toolbar to the FEM workbench: {}\n".format(e))  # noqa: F821
