# Run by `freecad` under Xvfb (tests/python/test_freecad_gui.py): drives the GUI with QTimer steps and clicks the
# task panel's own buttons. Checks: the FEM workbench shows the QualMesh toolbar; the command opens the task panel;
# Apply meshes; Cancel during a long run stops the process and keeps the previous mesh; a document saved headless
# gets its view provider back. Screenshots (`import -window root`) go to $QUALMESH_FC_SCREENS; facts go to
# $QUALMESH_FC_RESULT as JSON. The process ends with os._exit (status 1 on a failure or a timeout).

import json
import os
import subprocess
import time
import traceback

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

RESULT = {"errors": [], "steps": [], "screens": []}
SCREENS = os.environ["QUALMESH_FC_SCREENS"]
STATE = {}


def finish(code=0):
    with open(os.environ["QUALMESH_FC_RESULT"], "w") as f:
        json.dump(RESULT, f, indent=1)
    os._exit(code)


def screenshot(name):
    path = os.path.join(SCREENS, name + ".png")
    QtGui.QApplication.processEvents()
    try:
        subprocess.run(["import", "-window", "root", path], timeout=30, check=True)
        RESULT["screens"].append(path)
    except Exception as e:
        RESULT["steps"].append("screenshot {} failed: {}".format(name, e))


def main_window():
    return FreeCADGui.getMainWindow()


def qualmesh_children():
    """Pids of the qualmesh processes this FreeCAD started (children of this process)."""
    pids = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open("/proc/{}/stat".format(entry)) as f:
                fields = f.read().split()
        except OSError:
            continue
        if fields[1] == "(qualmesh)" and int(fields[3]) == os.getpid():
            pids.append(int(entry))
    return pids


def button(which):
    """The task dialog's standard button (Ok, Apply, Cancel)."""
    for box in main_window().findChildren(QtGui.QDialogButtonBox):
        b = box.button(which)
        if b is not None and b.isVisible():
            return b
    return None


def step(function, delay_ms=300):
    def run():
        try:
            RESULT["steps"].append(function.__name__)
            function()
        except Exception:
            RESULT["errors"].append(traceback.format_exc())
            screenshot("failure")
            finish(1)
    QtCore.QTimer.singleShot(delay_ms, run)


def wait_for(condition, then, timeout_s, what):
    deadline = time.time() + timeout_s

    def poll():
        try:
            if condition():
                step(then, 100)
            elif time.time() > deadline:
                RESULT["errors"].append("timed out waiting for " + what)
                screenshot("timeout")
                finish(1)
            else:
                QtCore.QTimer.singleShot(200, poll)
        except Exception:
            RESULT["errors"].append(traceback.format_exc())
            finish(1)
    QtCore.QTimer.singleShot(200, poll)


def widen_combo_view(width=560):
    mw = main_window()
    docks = [d for d in mw.findChildren(QtGui.QDockWidget) if d.objectName() in ("Combo View", "ComboView")
             or d.windowTitle() == "Combo View"]
    if docks and hasattr(mw, "resizeDocks"):
        mw.resizeDocks(docks[:1], [width], QtCore.Qt.Horizontal)


def toolbar_crop(bar, name):
    """A crop of the screenshot around one toolbar (its screen geometry, with a margin), 2x enlarged."""
    full = os.path.join(SCREENS, name + ".png")
    top_left = bar.mapToGlobal(QtCore.QPoint(0, 0))
    x, y = max(0, top_left.x() - 200), max(0, top_left.y() - 10)
    out = os.path.join(SCREENS, name + "_zoom.png")
    try:
        subprocess.run(["convert", full, "-crop", "{}x{}+{}+{}".format(bar.width() + 400, bar.height() + 20, x, y),
                        "+repage", "-resize", "200%", out], timeout=30, check=True)
        RESULT["screens"].append(out)
    except Exception as e:
        RESULT["steps"].append("crop failed: {}".format(e))


def s1_fem_workbench():
    FreeCADGui.activateWorkbench("FemWorkbench")
    widen_combo_view()
    QtGui.QApplication.processEvents()
    bars = [b for b in main_window().findChildren(QtGui.QToolBar) if b.windowTitle() == "QualMesh"]
    RESULT["fem_toolbar"] = {"found": bool(bars), "visible": any(b.isVisible() for b in bars),
                             "actions": [a.text() for b in bars for a in b.actions()]}
    doc = FreeCAD.newDocument("GuiCheck")
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 100, 10, 10
    import ObjectsFem
    import FemGui
    analysis = ObjectsFem.makeAnalysis(doc, "Analysis")
    FemGui.setActiveAnalysis(analysis)
    doc.recompute()
    FreeCADGui.SendMsgToActiveView("ViewFit")
    FreeCADGui.ActiveDocument.ActiveView.viewIsometric()
    FreeCADGui.Selection.clearSelection()
    FreeCADGui.Selection.addSelection(doc.Box)
    STATE["doc"] = doc
    STATE["bars"] = bars
    step(s2_open_panel, 1500)


def s2_open_panel():
    screenshot("1_fem_workbench_toolbar")
    if STATE["bars"]:
        toolbar_crop(STATE["bars"][0], "1_fem_workbench_toolbar")
        RESULT["fem_toolbar"]["enabled_with_selection"] = all(a.isEnabled() for a in STATE["bars"][0].actions()
                                                              if a.text())
    doc = STATE["doc"]
    FreeCADGui.runCommand("QualMesh_MeshFromShape")
    QtGui.QApplication.processEvents()
    objs = [o for o in doc.Objects if getattr(getattr(o, "Proxy", None), "Type", "") == "QualMesh::FemMeshQualMesh"]
    panel = main_window().findChild(QtGui.QWidget, "QualMeshTaskPanel")
    RESULT["panel"] = {"mesh_objects": len(objs), "open": panel is not None and panel.isVisible(),
                       "in_analysis": bool(objs) and objs[0] in doc.Analysis.Group,
                       "dialog": FreeCADGui.Control.activeDialog()}
    STATE["obj"] = objs[0]
    panel.findChild(QtGui.QWidget, "if_max").setProperty("rawValue", 5.0)
    button(QtGui.QDialogButtonBox.Apply).click()
    wait_for(lambda: STATE["obj"].FemMesh.NodeCount > 0 and not qualmesh_children(), s3_meshed, 60, "Apply's mesh")


def s3_meshed():
    obj = STATE["obj"]
    doc = STATE["doc"]
    doc.Box.ViewObject.hide()
    FreeCADGui.SendMsgToActiveView("ViewFit")
    QtGui.QApplication.processEvents()
    log = main_window().findChild(QtGui.QPlainTextEdit, "te_output").toPlainText()
    RESULT["apply"] = {"nodes": obj.FemMesh.NodeCount, "volumes": obj.FemMesh.VolumeCount, "Nodes": obj.Nodes,
                       "log_has_summary": "output:" in log and "QualMesh done" in log,
                       "progress": main_window().findChild(QtGui.QProgressBar, "progress").value()}
    STATE["before_cancel"] = (obj.FemMesh.NodeCount, obj.FemMesh.VolumeCount, obj.Nodes, obj.Tetrahedra)
    screenshot("2_applied_mesh_and_log")
    panel = main_window().findChild(QtGui.QWidget, "QualMeshTaskPanel")
    panel.findChild(QtGui.QWidget, "if_max").setProperty("rawValue", 0.3)  # about 1.5M tets: still running when cancelled
    button(QtGui.QDialogButtonBox.Apply).click()
    STATE["long_started"] = time.time()
    wait_for(lambda: bool(qualmesh_children()) and time.time() - STATE["long_started"] > 2.5, s4_cancel, 20,
             "the long run")


def s4_cancel():
    RESULT["long_run"] = {"children_before_cancel": len(qualmesh_children()),
                          "progress": main_window().findChild(QtGui.QProgressBar, "progress").value()}
    screenshot("3_long_run_in_progress")
    STATE["cancel_clicked"] = time.time()
    button(QtGui.QDialogButtonBox.Cancel).click()
    wait_for(lambda: not qualmesh_children(), s5_cancelled, 15, "the process to end after Cancel")


def s5_cancelled():
    obj = STATE["obj"]
    QtGui.QApplication.processEvents()
    panel = main_window().findChild(QtGui.QWidget, "QualMeshTaskPanel")
    log = panel.findChild(QtGui.QPlainTextEdit, "te_output").toPlainText() if panel else ""
    RESULT["cancel"] = {"stopped_s": time.time() - STATE["cancel_clicked"],
                        "unchanged": (obj.FemMesh.NodeCount, obj.FemMesh.VolumeCount, obj.Nodes, obj.Tetrahedra)
                        == STATE["before_cancel"],
                        "panel_still_open": panel is not None and panel.isVisible(),
                        "log_says_cancelled": "cancelled" in log}
    screenshot("4_cancelled_previous_mesh_kept")
    if panel is not None and panel.isVisible():
        button(QtGui.QDialogButtonBox.Cancel).click()
    step(s6_headless_document, 500)


def s6_headless_document():
    RESULT["panel_closed"] = main_window().findChild(QtGui.QWidget, "QualMeshTaskPanel") is None or \
        not main_window().findChild(QtGui.QWidget, "QualMeshTaskPanel").isVisible()
    path = os.environ.get("QUALMESH_FC_HEADLESS_DOC")
    if path:
        doc = FreeCAD.openDocument(path)
        from qualmesh_fem import view_mesh_qualmesh
        meshes = [o for o in doc.Objects if getattr(getattr(o, "Proxy", None), "Type", "") ==
                  "QualMesh::FemMeshQualMesh"]
        for o in meshes:
            o.ViewObject.show()
            FreeCADGui.Selection.addSelection(o)
        RESULT["headless_doc"] = {
            "meshes": len(meshes),
            "view_provider": all(isinstance(o.ViewObject.Proxy, view_mesh_qualmesh.VPMeshQualMesh) for o in meshes),
            "nodes": meshes[0].FemMesh.NodeCount if meshes else 0}
        FreeCADGui.SendMsgToActiveView("ViewFit")
        FreeCADGui.ActiveDocument.ActiveView.viewIsometric()
        step(s7_done, 1000)
    else:
        step(s7_done, 100)


def s7_done():
    screenshot("5_headless_document_in_gui")
    FreeCADGui.activateWorkbench("QualMeshWorkbench")
    QtGui.QApplication.processEvents()
    bars = [b for b in main_window().findChildren(QtGui.QToolBar) if b.windowTitle() == "QualMesh" and b.isVisible()]
    RESULT["own_workbench"] = {"active": FreeCADGui.activeWorkbench().name(),
                               "actions": [a.text() for b in bars for a in b.actions() if a.text()]}
    finish(0)


QtCore.QTimer.singleShot(int(os.environ.get("QUALMESH_FC_GUI_TIMEOUT_MS", "150000")),
                         lambda: (RESULT["errors"].append("watchdog timeout"), screenshot("watchdog"), finish(1)))
step(s1_fem_workbench, 2000)
