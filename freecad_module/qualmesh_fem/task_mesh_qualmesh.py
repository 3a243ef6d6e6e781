# QualMesh FEM mesher for FreeCAD: the task panel, as FEM's femtaskpanels/task_mesh_gmsh.py.
#
# Apply writes the panel's values into the object and starts qualmesh without blocking the GUI: a 100 ms timer
# streams the mesher's log into the panel, moves the progress bar through the stages `qualmesh -v` reports and,
# when the process has ended, reads the mesh and assigns it (one undoable transaction). Cancel during a run
# terminates the process and keeps the panel open with the previous mesh untouched; Cancel again closes it.
# OK while a run is in flight does nothing but say so.

import time

from PySide import QtCore
from PySide import QtGui

import FreeCAD
import FreeCADGui

from . import mesh_qualmesh
from . import qualmeshtools
from . import view_mesh_qualmesh


class _TaskPanel(object):
    """Task panel of a QualMesh mesh object."""

    def __init__(self, obj):
        self.mesh_obj = obj
        self.tools = None
        self.start_time = None
        self.last_result = None
        self.form = self._make_form()
        self.timer = QtCore.QTimer()
        self.timer.setInterval(100)
        self.timer.timeout.connect(self.update_run)
        self.get_mesh_params()

    # -- widgets ---------------------------------------------------------------------------------------------
    def _make_form(self):
        form = QtGui.QWidget()
        form.setObjectName("QualMeshTaskPanel")
        form.setWindowTitle("FEM mesh by QualMesh")
        form.setWindowIcon(QtGui.QIcon(view_mesh_qualmesh.icon_path()))
        layout = QtGui.QVBoxLayout(form)

        params = QtGui.QGroupBox("Mesh parameters")
        grid = QtGui.QFormLayout(params)
        loader = FreeCADGui.UiLoader()
        self.if_max = loader.createWidget("Gui::QuantitySpinBox")
        self.if_max.setObjectName("if_max")
        self.if_max.setProperty("unit", "mm")
        self.if_max.setToolTip("Longest element edge (0 = automatic)")
        self.if_min = loader.createWidget("Gui::QuantitySpinBox")
        self.if_min.setObjectName("if_min")
        self.if_min.setProperty("unit", "mm")
        self.cb_order = QtGui.QComboBox()
        self.cb_order.setObjectName("cb_order")
        self.cb_order.addItems(mesh_qualmesh.MeshQualMesh.known_element_orders)
        self.sb_radius_edge = QtGui.QDoubleSpinBox()
        self.sb_radius_edge.setObjectName("sb_radius_edge")
        self.sb_radius_edge.setRange(1.1, 100.0)
        self.sb_radius_edge.setSingleStep(0.1)
        self.sb_sliver = QtGui.QDoubleSpinBox()
        self.sb_sliver.setObjectName("sb_sliver")
        self.sb_sliver.setRange(0.1, 59.9)
        self.sb_sliver.setSuffix(" deg")
        self.ck_pumping = QtGui.QCheckBox("Remove slivers by pumping")
        self.ck_pumping.setObjectName("ck_pumping")
        grid.addRow("Max element size:", self.if_max)
        grid.addRow("Min element size:", self.if_min)
        grid.addRow("Element order:", self.cb_order)
        grid.addRow("Radius-edge bound:", self.sb_radius_edge)
        grid.addRow("Sliver angle:", self.sb_sliver)
        grid.addRow(self.ck_pumping)
        layout.addWidget(params)

        run = QtGui.QGroupBox("QualMesh")
        run_layout = QtGui.QVBoxLayout(run)
        self.progress = QtGui.QProgressBar()
        self.progress.setObjectName("progress")
        self.progress.setRange(0, 100)
        self.l_time = QtGui.QLabel("Time: 0.0 s")
        self.l_time.setObjectName("l_time")
        self.l_stats = QtGui.QLabel("")
        self.l_stats.setObjectName("l_stats")
        self.l_stats.setWordWrap(True)
        self.te_output = QtGui.QPlainTextEdit()
        self.te_output.setObjectName("te_output")
        self.te_output.setReadOnly(True)
        self.te_output.setMinimumHeight(220)
        self.te_output.setLineWrapMode(QtGui.QPlainTextEdit.NoWrap)
        run_layout.addWidget(self.progress)
        run_layout.addWidget(self.l_time)
        run_layout.addWidget(self.l_stats)
        run_layout.addWidget(self.te_output)
        layout.addWidget(run)
        return form

    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Apply | QtGui.QDialogButtonBox.Cancel)

    # -- values between panel and object ---------------------------------------------------------------------
    def get_mesh_params(self):
        obj = self.mesh_obj
        self.if_max.setProperty("rawValue", obj.CharacteristicLengthMax.Value)
        self.if_min.setProperty("rawValue", obj.CharacteristicLengthMin.Value)
        self.cb_order.setCurrentIndex(self.cb_order.findText(obj.ElementOrder))
        self.sb_radius_edge.setValue(obj.RadiusEdgeBound)
        self.sb_sliver.setValue(obj.SliverAngle.Value)
        self.ck_pumping.setChecked(obj.Pumping)
        self.show_statistics()

    def set_mesh_params(self):
        obj = self.mesh_obj
        obj.CharacteristicLengthMax = float(self.if_max.property("rawValue"))
        obj.CharacteristicLengthMin = float(self.if_min.property("rawValue"))
        obj.ElementOrder = str(self.cb_order.currentText())
        obj.RadiusEdgeBound = self.sb_radius_edge.value()
        obj.SliverAngle = self.sb_sliver.value()
        obj.Pumping = self.ck_pumping.isChecked()

    def show_statistics(self):
        obj = self.mesh_obj
        if obj.Nodes:
            self.l_stats.setText("{} nodes, {} tetrahedra, min dihedral angle {:.2f} deg, {} below 10 deg".format(
                obj.Nodes, obj.Tetrahedra, obj.MinDihedralAngle.Value, obj.TetsBelow10Deg))
        else:
            self.l_stats.setText("no mesh yet")

    # -- buttons ---------------------------------------------------------------------------------------------
    @property
    def running(self):
        return self.tools is not None and self.tools.run is not None and self.tools.run.running

    def clicked(self, button):
        if button == QtGui.QDialogButtonBox.Apply:
            self.run_qualmesh()

    def accept(self):
        if self.running:
            self.console_log("QualMesh is still running: wait for it, or Cancel to stop it", "#B00000")
            return False
        self.set_mesh_params()
        self._close()
        return True

    def reject(self):
        if self.running:
            self.cancel_run()
            return False
        self._close()
        return True

    def _close(self):
        self.timer.stop()
        FreeCADGui.ActiveDocument.resetEdit()
        self.mesh_obj.Document.recompute()

    # -- the run ---------------------------------------------------------------------------------------------
    def console_log(self, message, color="#000000"):
        elapsed = time.time() - self.start_time if self.start_time else 0.0
        self.te_output.appendHtml('<font color="#0000FF">{:5.1f}:</font> <font color="{}">{}</font>'.format(
            elapsed, color, _escape(message)))

    def run_qualmesh(self):
        if self.running:
            return
        self.set_mesh_params()
        self.te_output.clear()
        self.progress.setValue(0)
        self.start_time = time.time()
        self.console_log("Start QualMesh ...")
        self.tools = qualmeshtools.QualMeshTools(self.mesh_obj, _active_analysis())
        try:
            self.tools.start(log=lambda line: self.console_log(line, "#606060"))
        except Exception as e:
            self.tools = None
            self.console_log("QualMesh could not start: {}".format(e), "#FF0000")
            FreeCAD.Console.PrintError("QualMesh could not start: {}\n".format(e))
            return
        self.timer.start()

    def update_run(self):
        if self.tools is None or self.tools.run is None:
            return
        run = self.tools.run
        for stream, line in run.poll():
            self.console_log(line, "#000000" if stream == "out" else "#606060")
        self.progress.setValue(run.progress)
        self.l_time.setText("Time: {:.1f} s  ({})".format(time.time() - self.start_time, run.stage))
        if not run.running:
            self.timer.stop()
            self.finish_run()

    def finish_run(self):
        if not self.tools.run.cancelled:
            self.progress.setValue(92)
            self.console_log("reading the mesh into FreeCAD ...")
            QtGui.QApplication.processEvents()
        doc = self.mesh_obj.Document
        doc.openTransaction("Mesh by QualMesh")
        QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
        try:
            result = self.tools.finish()
        finally:
            QtGui.QApplication.restoreOverrideCursor()
        if result.succeeded:
            doc.commitTransaction()
        else:
            doc.abortTransaction()
        self.last_result = result
        for w in result.warnings:
            self.console_log("warning: " + w, "#B06000")
        if result.succeeded:
            self.progress.setValue(100)
            t = result.timings_s
            self.console_log("QualMesh done: mesher {:.1f} s, reading {:.1f} s, assigning {:.1f} s".format(
                t["mesher"], t["read"], t["assign"]), "#008000")
            FreeCAD.Console.PrintMessage("QualMesh: {} nodes, {} tetrahedra\n".format(
                result.statistics["nodes"], result.statistics["tetrahedra"]))
        elif result.status == qualmeshtools.MeshRunStatus.CANCELLED:
            self.progress.setValue(0)
            self.console_log("QualMesh {}: the previous mesh is kept".format(result.message), "#B00000")
        else:
            self.progress.setValue(0)
            self.console_log("QualMesh failed, the previous mesh is kept:", "#FF0000")
            self.console_log(result.message, "#FF0000")
            FreeCAD.Console.PrintError("QualMesh failed: {}\n".format(result.message))
        self.l_time.setText("Time: {:.1f} s  ({})".format(time.time() - self.start_time, result.status))
        self.show_statistics()
        self.tools = None

    def cancel_run(self):
        if self.running:
            self.console_log("cancelling ...", "#B00000")
            self.tools.cancel()
            self.update_run()


def _escape(text):
    return str(text).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


def _active_analysis():
    try:
        import FemGui
        return FemGui.getActiveAnalysis()
    except ImportError:
        return None
