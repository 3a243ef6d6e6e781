# QualMesh FEM mesher for FreeCAD: the tool that runs the `qualmesh` executable and hands FreeCAD the mesh.
#
# Modelled on FEM's femmesh/gmshtools.py: the shape is written as BREP into a temporary folder, `qualmesh mesh`
# runs as a subprocess (a crash never takes FreeCAD down, and a run can be cancelled: the process group is
# terminated), its CalculiX deck is read into a new Fem.FemMesh (meshreader.py) and only then, when everything
# succeeded, assigned to the mesh object. A failure or a cancel leaves the document as it was: the previous mesh,
# the statistics and every other property untouched.
#
# Face numbering: QualMesh numbers the faces, edges and solids of the healed shape in TopExp::MapShapes order, which
# is FreeCAD's Face<i>/Edge<i>/Solid<i> naming of the same shape written as BREP; the counts are compared after
# each run, and a mismatch (healing changed the topology) is reported as a warning.
#
# Sizes: CharacteristicLengthMax maps to `--size` when the executable has it, else to `--max-edge` (0 = automatic:
# no option). CharacteristicLengthMin and MeshRegionList map to `--min-size` and `--local-size Face3=0.5` when the
# executable has them; otherwise the run says, in its log and its result's warnings, that they were ignored.

import os
import queue
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

PREFERENCE_GROUP = "User parameter:BaseApp/Preferences/Mod/QualMesh"


class QualMeshError(Exception):
    """Meshing failed: no executable, a shape it cannot mesh, a deck it cannot read. The message says which."""


class QualMeshCancelled(QualMeshError):
    """The run was cancelled (the process was terminated); nothing was changed."""


class MeshRunStatus(object):
    SUCCEEDED = "succeeded"
    FAILED = "failed"
    CANCELLED = "cancelled"


class MeshRunResult(object):
    """Outcome of QualMeshTools.create_mesh().

    status: a MeshRunStatus value; message: why it failed (empty on success); warnings: list of str;
    statistics: {"nodes", "tetrahedra", "min_dihedral_deg", "tets_below_10_deg", ...} (empty unless succeeded);
    timings_s: {"mesher", "read", "assign"} wall seconds; log: the mesher's output lines.
    """

    def __init__(self, status, message="", warnings=None, statistics=None, timings_s=None, log=None):
        self.status = status
        self.message = message
        self.warnings = warnings or []
        self.statistics = statistics or {}
        self.timings_s = timings_s or {}
        self.log = log or []

    @property
    def succeeded(self):
        return self.status == MeshRunStatus.SUCCEEDED

    def __repr__(self):
        return "MeshRunResult({}, {!r}, {})".format(self.status, self.message, self.statistics)


class MeshParameters(object):
    """What the user asked for, in model units (mm) and degrees.

    max_size, min_size: 0 = automatic; order: 1 or 2; radius_edge: radius-edge ratio bound (>= 1.1);
    sliver_angle_deg: a tetrahedron with a smaller dihedral angle is a sliver; pumping: sliver pumping on/off;
    local_sizes: {"Face3": 0.5, "Edge5": 0.2, "Solid2": 1.0}.
    """

    def __init__(self, max_size=0.0, min_size=0.0, order=2, radius_edge=2.0, sliver_angle_deg=15.0, pumping=True,
                 local_sizes=None):
        self.max_size = float(max_size)
        self.min_size = float(min_size)
        self.order = int(order)
        self.radius_edge = float(radius_edge)
        self.sliver_angle_deg = float(sliver_angle_deg)
        self.pumping = bool(pumping)
        self.local_sizes = dict(local_sizes or {})


# ----------------------------------------------------------------------------------------------------------------
# the executable

def _preference_path():
    try:
        import FreeCAD
        return FreeCAD.ParamGet(PREFERENCE_GROUP).GetString("QualMeshBinaryPath", "")
    except ImportError:
        return ""


def find_qualmesh():
    """Path of the `qualmesh` executable: $QUALMESH_EXE, else the preference QualMeshBinaryPath (group
    Mod/QualMesh), else `qualmesh` on PATH, else where `cmake --install` put it. Raises QualMeshError."""
    candidates = [("QUALMESH_EXE", os.environ.get("QUALMESH_EXE", "")),
                  ("preference QualMeshBinaryPath", _preference_path()),
                  ("PATH", shutil.which("qualmesh") or "")]
    try:
        from . import _build_config
        candidates.append(("install", _build_config.QUALMESH_INSTALLED_EXE))
    except ImportError:
        pass
    for origin, path in candidates:
        if path:
            if os.path.isfile(path) and os.access(path, os.X_OK):
                return path
            if origin != "install":
                raise QualMeshError("qualmesh executable '{}' (from {}) does not exist or is not executable"
                                    .format(path, origin))
    raise QualMeshError("qualmesh executable not found: set QUALMESH_EXE, the preference "
                        "'{}/QualMeshBinaryPath', or put qualmesh on PATH".format(PREFERENCE_GROUP))


_capabilities_cache = {}


def mesh_options(exe):
    """The set of long options `qualmesh mesh --help` lists ('--max-edge', '--size', ...)."""
    key = (exe, os.path.getmtime(exe))
    if key not in _capabilities_cache:
        try:
            out = subprocess.run([exe, "mesh", "--help"], capture_output=True, text=True, timeout=30).stdout
        except (OSError, subprocess.SubprocessError) as e:
            raise QualMeshError("cannot run '{} mesh --help': {}".format(exe, e))
        _capabilities_cache[key] = {word.split("=")[0].rstrip(",") for word in out.split() if word.startswith("--")}
    return _capabilities_cache[key]


def build_command(exe, input_path, output_path, params, options):
    """The argument list of one run, and the warnings about what this executable cannot do."""
    args = [exe, "mesh", input_path, "-o", output_path, "--order", str(params.order), "-v"]
    warnings = []
    if params.max_size > 0:
        args += ["--size" if "--size" in options else "--max-edge", repr(params.max_size)]
    if params.min_size > 0:
        if "--min-size" in options:
            args += ["--min-size", repr(params.min_size)]
        else:
            warnings.append("CharacteristicLengthMin ignored: this qualmesh has no --min-size option")
    if params.local_sizes:
        if "--local-size" in options:
            for name in sorted(params.local_sizes):
                args += ["--local-size", "{}={!r}".format(name, params.local_sizes[name])]
        else:
            warnings.append("MeshRegionList ignored ({}): this qualmesh has no --local-size option".format(
                ", ".join("{}={}".format(k, v) for k, v in sorted(params.local_sizes.items()))))
    args += ["--radius-edge", repr(params.radius_edge), "--sliver-angle", repr(params.sliver_angle_deg)]
    if not params.pumping:
        args.append("--no-pump")
    return args, warnings


# ----------------------------------------------------------------------------------------------------------------
# one run of the executable

# Coarse progress (percent) from the stages `qualmesh -v` logs on stderr, then the summary on stdout; the reading
# into FreeCAD takes the last steps.
_STAGES = (("validation", 5, "validating the model"), ("input:", 10, "model read"),
           ("regions", 15, "refining"), ("refinement", 25, "refining"),
           ("rule 4", 40, "Rule 4 (slivers near the boundary)"),
           ("pumping", 55, "pumping weights"), ("sliver insertion", 70, "points at slivers"),
           ("cad fit", 88, "mesh written"), ("output:", 90, "mesh written"))


class QualMeshRun(object):
    """One `qualmesh mesh` subprocess, read without blocking: start(), then poll() from a timer (GUI) or wait().

    Lines of stdout and stderr are read by two threads into a queue; poll() hands them over and updates progress.
    cancel() terminates the process group (SIGTERM, then SIGKILL after `grace_s`).
    """

    def __init__(self, args, cwd=None):
        self.args = list(args)
        self.cwd = cwd
        self.process = None
        self.lines = []
        self.stdout_lines = []
        self.progress = 0
        self.stage = "starting"
        self.cancelled = False
        self.started_at = None
        self.finished_at = None
        self._queue = queue.Queue()
        self._readers = []

    def start(self):
        kwargs = {}
        if hasattr(os, "setsid"):
            kwargs["start_new_session"] = True
        try:
            self.process = subprocess.Popen(self.args, cwd=self.cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                            stdin=subprocess.DEVNULL, text=True, bufsize=1, **kwargs)
        except OSError as e:
            raise QualMeshError("cannot start {}: {}".format(self.args[0], e))
        self.started_at = time.time()
        for stream, name in ((self.process.stdout, "out"), (self.process.stderr, "err")):
            reader = threading.Thread(target=self._read, args=(stream, name), daemon=True)
            reader.start()
            self._readers.append(reader)
        return self

    def _read(self, stream, name):
        for line in iter(stream.readline, ""):
            self._queue.put((name, line.rstrip("\n")))
        stream.close()

    def poll(self):
        """New (stream, line) pairs since the last call; updates progress, stage and returncode."""
        new = []
        while True:
            try:
                stream, line = self._queue.get_nowait()
            except queue.Empty:
                break
            new.append((stream, line))
            self.lines.append(line)
            if stream == "out":
                self.stdout_lines.append(line)
            text = line[len("qualmesh: "):] if line.startswith("qualmesh: ") else line
            for key, percent, stage in _STAGES:
                if text.startswith(key) and percent > self.progress:
                    self.progress, self.stage = percent, stage
        if self.process is not None and self.process.poll() is not None and self.finished_at is None:
            if all(not r.is_alive() for r in self._readers) and self._queue.empty():
                self.finished_at = time.time()
        return new

    @property
    def running(self):
        return self.process is not None and self.finished_at is None

    @property
    def returncode(self):
        return None if self.process is None else self.process.poll()

    @property
    def elapsed_s(self):
        if self.started_at is None:
            return 0.0
        return (self.finished_at or time.time()) - self.started_at

    def cancel(self, grace_s=2.0):
        """Terminate the run (its whole process group); returns once the process is gone."""
        if self.process is None or self.process.poll() is not None:
            return
        self.cancelled = True
        self._signal(signal.SIGTERM)
        try:
            self.process.wait(timeout=grace_s)
        except subprocess.TimeoutExpired:
            self._signal(signal.SIGKILL)
            self.process.wait()

    def _signal(self, sig):
        try:
            if hasattr(os, "killpg"):
                os.killpg(self.process.pid, sig)
            else:
                self.process.send_signal(sig)
        except ProcessLookupError:
            pass

    def wait(self, on_lines=None, cancel_event=None, period_s=0.1):
        """Block until the run ends; hands new lines to on_lines(list of (stream, line)) and cancels when
        cancel_event (a threading.Event) is set. Returns the exit status."""
        while True:
            new = self.poll()
            if new and on_lines is not None:
                on_lines(new)
            if not self.running:
                return self.returncode
            if cancel_event is not None and cancel_event.is_set():
                self.cancel()
            time.sleep(period_s)

    def summary_value(self, prefix):
        """The stdout summary line starting with `prefix` ('output:', 'quality:'), or ''."""
        for line in self.stdout_lines:
            if line.startswith(prefix):
                return line
        return ""

    def error_text(self):
        """The last lines of the log, for a failure message."""
        tail = [l for l in self.lines if l.strip()][-8:]
        return "\n".join(tail)


def exit_status_meaning(code):
    return {1: "internal error (a bug in qualmesh: please report it with the model)",
            2: "bad input or usage", 3: "the mesh check found defects",
            4: "a limit stopped meshing: time, memory, vertex count or double precision (the message says which)"}.get(
        code, "killed by signal {}".format(-code) if code is not None and code < 0 else "exit status {}".format(code))


# ----------------------------------------------------------------------------------------------------------------
# shape -> Fem.FemMesh

class WorkingDir(object):
    """A temporary folder for one run, removed afterwards unless QUALMESH_FEM_KEEP is set or the preference
    KeepWorkingFiles is true (then its path is logged)."""

    def __init__(self):
        self.path = tempfile.mkdtemp(prefix="qualmesh_fem_")

    def keep(self):
        if os.environ.get("QUALMESH_FEM_KEEP"):
            return True
        try:
            import FreeCAD
            return FreeCAD.ParamGet(PREFERENCE_GROUP).GetBool("KeepWorkingFiles", False)
        except ImportError:
            return False

    def cleanup(self):
        if not self.keep():
            shutil.rmtree(self.path, ignore_errors=True)


def check_shape(shape):
    """Raise QualMeshError unless the shape has at least one solid."""
    if shape is None or shape.isNull():
        raise QualMeshError("the shape to mesh is empty")
    if not shape.Solids:
        raise QualMeshError("the shape to mesh has no solid (it is a {} with {} faces): QualMesh meshes volumes"
                            .format(shape.ShapeType, len(shape.Faces)))


def result_format():
    """The mesh file qualmesh writes for FreeCAD: "inp" (read with numpy by meshreader.py, default) or "unv" (read
    by Fem.read, unvreader.py); environment QUALMESH_FEM_READER or the preference Reader (group Mod/QualMesh).
    Measured on 1.05M C3D10 (1.45M nodes), same process, shared 2-core machine: inp 16.5-23.4 s, unv 28.4-36.5 s
    to a Fem.FemMesh with statistics, plus 3.3-4.0 s to assign it either way."""
    import os as _os
    value = _os.environ.get("QUALMESH_FEM_READER", "")
    if not value:
        try:
            import FreeCAD
            value = FreeCAD.ParamGet(PREFERENCE_GROUP).GetString("Reader", "")
        except ImportError:
            value = ""
    return value if value in ("unv", "inp") else "inp"


def read_result(mesh_path, shape=None):
    """(Fem.FemMesh, statistics, warnings) from the mesh file qualmesh wrote (.unv or .inp); statistics as in
    MeshRunResult. With a shape, the group names are checked against it and renamed where they differ."""
    from . import entitymatch, meshreader, unvreader
    warnings = []
    try:
        if mesh_path.endswith(".unv"):
            mesh, deck = unvreader.read_unv(mesh_path)
        else:
            deck = meshreader.parse_deck(mesh_path)
            mesh = None
        renaming = {}
        if shape is not None:
            renaming, match_warnings = entitymatch.freecad_names(deck, shape)
            warnings += match_warnings
            if renaming:
                entitymatch.rename_groups(deck, renaming)
                warnings.append("groups renamed to FreeCAD's names of the same entities: " + ", ".join(
                    "{}->{}".format(k, v) for k, v in sorted(renaming.items())))
        if mesh is None:
            mesh = meshreader.build_femmesh(deck)
        elif renaming:
            unvreader.rename_femmesh_groups(mesh, renaming)
        quality = meshreader.quality_figures(deck)
    except (meshreader.DeckError, OSError, ValueError, IndexError) as e:
        raise QualMeshError("cannot read the mesh: {}".format(e))
    nodes_per_tet = len(mesh.getElementNodes(mesh.Volumes[0])) if mesh.VolumeCount else 0
    statistics = {"nodes": int(mesh.NodeCount), "tetrahedra": int(mesh.VolumeCount),
                  "min_dihedral_deg": quality["min_dihedral_deg"],
                  "tets_below_10_deg": quality["num_tets_below_10_deg"],
                  "tets_below_5_deg": quality["num_tets_below_5_deg"],
                  "element_order": 2 if nodes_per_tet == 10 else 1}
    if shape is not None:
        faces = sum(1 for name in deck.node_sets if name.startswith("Face"))
        solids = sum(1 for name in deck.solids if name.startswith("Solid"))
        if faces != len(shape.Faces) or solids != len(shape.Solids):
            warnings.append("the mesh has {} face and {} solid groups, the shape {} faces and {} solids: "
                            "Face<i> may not be FreeCAD's Face<i>".format(faces, solids, len(shape.Faces),
                                                                         len(shape.Solids)))
    return mesh, statistics, warnings


def mesh_shape(shape, max_size=0.0, order=2, min_size=0.0, radius_edge=2.0, sliver_angle_deg=15.0, pumping=True,
               local_sizes=None, log=None, cancel_event=None, timings=None):
    """Mesh a Part.Shape with QualMesh and return a new Fem.FemMesh (groups Solid<i>, Face<i>, Edge<i>).

    max_size, min_size in model units (0 = automatic); order 1 or 2; log(line) receives the mesher's output;
    cancel_event (threading.Event) cancels the run. Raises QualMeshError (QualMeshCancelled on cancel).
    Mutates nothing outside its temporary folder.
    """
    params = MeshParameters(max_size, min_size, order, radius_edge, sliver_angle_deg, pumping, local_sizes)
    mesh, statistics, _ = _run(shape, params, log, cancel_event, timings)
    return mesh


def _run(shape, params, log=None, cancel_event=None, timings=None, on_start=None):
    check_shape(shape)
    exe = find_qualmesh()
    work = WorkingDir()
    try:
        brep = os.path.join(work.path, "shape.brep")
        deck = os.path.join(work.path, "mesh." + result_format())
        shape.exportBrep(brep)
        args, warnings = build_command(exe, brep, deck, params, mesh_options(exe))
        for w in warnings:
            if log:
                log("warning: " + w)
        run = QualMeshRun(args, cwd=work.path).start()
        if on_start:
            on_start(run)
        run.wait(on_lines=(lambda lines: [log(l) for _, l in lines]) if log else None, cancel_event=cancel_event)
        if run.cancelled:
            raise QualMeshCancelled("cancelled after {:.1f} s".format(run.elapsed_s))
        if run.returncode != 0:
            raise QualMeshError("qualmesh failed ({}):\n{}".format(exit_status_meaning(run.returncode),
                                                                     run.error_text()))
        t0 = time.time()
        mesh, statistics, read_warnings = read_result(deck, shape)
        if timings is not None:
            timings["mesher"] = run.elapsed_s
            timings["read"] = time.time() - t0
        for w in read_warnings:
            if log:
                log("warning: " + w)
        return mesh, statistics, warnings + read_warnings
    finally:
        if work.keep() and log:
            log("working files kept in " + work.path)
        work.cleanup()


# ----------------------------------------------------------------------------------------------------------------
# the mesh object's tool

def parameters_of(mesh_obj):
    """MeshParameters from a QualMesh mesh object's properties (units: mm, degrees)."""
    from FreeCAD import Units
    local_sizes = {}
    for region in getattr(mesh_obj, "MeshRegionList", []) or []:
        length = Units.Quantity(region.CharacteristicLength).Value
        if length <= 0 or not region.References:
            continue
        for ref_obj, names in region.References:
            for name in names:
                name = _element_in_part(mesh_obj.Part, ref_obj, name)
                if name:
                    local_sizes[name] = min(length, local_sizes.get(name, length))
    return MeshParameters(
        max_size=Units.Quantity(mesh_obj.CharacteristicLengthMax).Value,
        min_size=Units.Quantity(mesh_obj.CharacteristicLengthMin).Value,
        order=1 if mesh_obj.ElementOrder == "1st" else 2,
        radius_edge=mesh_obj.RadiusEdgeBound,
        sliver_angle_deg=Units.Quantity(mesh_obj.SliverAngle).Value,
        pumping=mesh_obj.Pumping,
        local_sizes=local_sizes)


def _element_in_part(part_obj, ref_obj, name):
    """The name ('Face3') in the Part's shape of element `name` of ref_obj (found geometrically when ref_obj is not
    the Part, as gmshtools does), or None."""
    if ref_obj == part_obj or part_obj.Shape.isSame(ref_obj.Shape):
        return name
    from femtools import geomtools
    return geomtools.find_element_in_shape(part_obj.Shape, geomtools.get_element(ref_obj, name)) or None


class QualMeshTools(object):
    """Meshes a QualMesh mesh object's Part and sets its FemMesh, like FEM's GmshTools.

    Headless: result = QualMeshTools(obj).create_mesh(). The task panel calls start() and then, from a timer,
    poll_run() and finish(); cancel() stops the run. The object is changed only by a successful finish().
    """

    def __init__(self, mesh_obj, analysis=None):
        self.mesh_obj = mesh_obj
        self.analysis = analysis
        self.part_obj = mesh_obj.Part
        self.run = None
        self.work = None
        self.deck_path = ""
        self.warnings = []
        self.log_lines = []

    def start(self, log=None):
        """Write the shape and start qualmesh; returns the QualMeshRun. Raises QualMeshError."""
        if self.part_obj is None:
            raise QualMeshError("{}: no Part to mesh".format(self.mesh_obj.Label))
        shape = self.part_obj.Shape
        check_shape(shape)
        exe = find_qualmesh()
        params = parameters_of(self.mesh_obj)
        self.work = WorkingDir()
        brep = os.path.join(self.work.path, self.part_obj.Name + "_Geometry.brep")
        self.deck_path = os.path.join(self.work.path, self.part_obj.Name + "_Mesh." + result_format())
        try:
            shape.exportBrep(brep)
            args, self.warnings = build_command(exe, brep, self.deck_path, params, mesh_options(exe))
            self.run = QualMeshRun(args, cwd=self.work.path).start()
        except Exception:
            self.work.cleanup()
            raise
        for w in self.warnings:
            self._log(log, "warning: " + w)
        self._log(log, " ".join(args))
        return self.run

    def _log(self, log, line):
        self.log_lines.append(line)
        if log:
            log(line)

    def cancel(self):
        if self.run is not None:
            self.run.cancel()

    def finish(self):
        """After the run ended: read the deck and, on success, assign FemMesh and the statistics. Returns a
        MeshRunResult; cleans the working folder."""
        run = self.run
        try:
            if run.cancelled:
                return MeshRunResult(MeshRunStatus.CANCELLED, "cancelled after {:.1f} s".format(run.elapsed_s),
                                     self.warnings, log=self.log_lines + run.lines)
            if run.returncode != 0:
                return MeshRunResult(MeshRunStatus.FAILED, "qualmesh failed ({}):\n{}".format(
                    exit_status_meaning(run.returncode), run.error_text()), self.warnings,
                    log=self.log_lines + run.lines)
            t0 = time.time()
            try:
                mesh, statistics, read_warnings = read_result(self.deck_path, self.part_obj.Shape)
            except QualMeshError as e:
                return MeshRunResult(MeshRunStatus.FAILED, str(e), self.warnings, log=self.log_lines + run.lines)
            t1 = time.time()
            self.mesh_obj.FemMesh = mesh
            self.mesh_obj.Nodes = statistics["nodes"]
            self.mesh_obj.Tetrahedra = statistics["tetrahedra"]
            self.mesh_obj.MinDihedralAngle = statistics["min_dihedral_deg"]
            self.mesh_obj.TetsBelow10Deg = statistics["tets_below_10_deg"]
            t2 = time.time()
            return MeshRunResult(MeshRunStatus.SUCCEEDED, "", self.warnings + read_warnings, statistics,
                                 {"mesher": run.elapsed_s, "read": t1 - t0, "assign": t2 - t1},
                                 self.log_lines + run.lines)
        finally:
            if self.work is not None:
                if self.work.keep():
                    self.log_lines.append("working files kept in " + self.work.path)
                self.work.cleanup()

    def create_mesh(self, log=None, cancel_event=None):
        """Mesh, blocking; returns a MeshRunResult (never raises for a meshing failure)."""
        try:
            self.start(log)
        except Exception as e:  # QualMeshError, or the shape's BREP export failing
            return MeshRunResult(MeshRunStatus.FAILED, str(e), log=self.log_lines)
        self.run.wait(on_lines=(lambda lines: [log(l) for _, l in lines]) if log else None,
                      cancel_event=cancel_event)
        return self.finish()


def print_to_console(line):
    """A log callback that writes to FreeCAD's report view / console."""
    try:
        import FreeCAD
        FreeCAD.Console.PrintMessage(line + "\n")
    except ImportError:
        sys.stdout.write(line + "\n")
