# QualMesh FEM mesher for FreeCAD: the toolbar QualMesh in FEM's own workbench, without patching FreeCAD.
#
# FreeCAD builds a workbench's custom toolbars from the parameter group
# User parameter:BaseApp/Workbench/<Workbench>/Toolbar/<Group>: the string "Name" is the title, every other string
# entry is a command name whose value is the module to import when the command is not registered yet, and the
# bool "Active" shows it. It is written once (marker FemToolbarInstalled in Mod/QualMesh), so a user who removes
# the toolbar through Tools > Customize keeps it removed.

import FreeCAD

from .qualmeshtools import PREFERENCE_GROUP

TOOLBAR_GROUP = "User parameter:BaseApp/Workbench/FemWorkbench/Toolbar/QualMesh"
TOOLBAR_TITLE = "QualMesh"


def install_fem_toolbar(force=False):
    """Add the QualMesh toolbar to the FEM workbench (once; again with force=True). Returns True if written."""
    prefs = FreeCAD.ParamGet(PREFERENCE_GROUP)
    if prefs.GetBool("FemToolbarInstalled", False) and not force:
        return False
    group = FreeCAD.ParamGet(TOOLBAR_GROUP)
    group.SetString("Name", TOOLBAR_TITLE)
    group.SetString("QualMesh_MeshFromShape", "qualmesh_fem.commands")
    group.SetBool("Active", True)
    prefs.SetBool("FemToolbarInstalled", True)
    return True
