"""The hostile-input catalogue of issue 18: what a new user types on the first day, and what `qualmesh` must answer.

Each case is a name, the argv after `qualmesh`, the exact exit code and a regular expression that stderr must match
(re.search; for exit 0 stderr must also be empty). Refused cases (exit != 0) must leave the output folder empty:
no mesh, no temporary file. Placeholders in argv:
  {in}/NAME         a file of inputs.py's INPUTS, written for the run
  {small}/NAME      tests/data/small/NAME
  {malformed}/NAME  tests/data/malformed/NAME (the readers' corpus; EXPECTED.tsv holds its messages)
  {shared}/PATH      ../shared/PATH (the third-party models; cases tagged needs:shared skip without it)
  {out}             the output mesh: OUT/mesh.vtu in an empty folder OUT
  {outdir}          that folder
The runner is tests/python/test_hostile.py; each case runs under a time limit (TIMEOUT_S, or the case's own) and,
where the platform allows, an address-space limit, so that a runaway case fails instead of hanging the suite.

Categories (issue 18, "What hostile input does today"):
  plc-*      1. inputs `info` marks INVALID: `mesh` refuses them as `info` does (exit 2, same words), writes nothing
  opt-*      2. every numeric option of `mesh`: NaN, infinities, 0, negative, out of range, not a number
  out-*      the output path: unknown extension, missing folder, a folder; checked before anything is read
  usage-*    the command line itself
  read-*     malformed files (tests/data/malformed), refused by the readers with their file, line and message
  ok-*       what works and must keep working (exit 0, a mesh written, nothing on stderr)
  far-*      5. models far from the origin: `check` and `mesh` work as at the origin
  limit-*    3. resource limits: exit 4, the limit named, nothing written unless --allow-partial (tag "writes")
  out-atomic-*, out-signal-*   4. output all or nothing: failed writes keep the old files, signals leave no temporary
  msg-*      7. messages: byte order mark, CR line ends, directories, random bytes, degenerate faces, overflow,
             empty .scad, --sewing-tolerance
"""
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import List

HERE = Path(__file__).resolve().parent
SOURCE_DIR = HERE.parents[1]
MALFORMED_DIR = SOURCE_DIR / "tests" / "data" / "malformed"

TIMEOUT_S = 30  # every case here takes well under a second; a case past this has run away


@dataclass
class Case:
    name: str
    argv: List[str]
    code: int
    stderr: str  # regular expression, re.search on the whole stderr
    timeout: float = TIMEOUT_S
    tags: List[str] = field(default_factory=list)
    stdout: str = ""  # regular expression, re.search on the whole stdout ("" matches anything)


CASES: List[Case] = []


def case(name, argv, code, stderr, **kw):
    assert all(c.name != name for c in CASES), name
    CASES.append(Case(name, list(argv), code, stderr, **kw))


BOX = "{small}/box.poly"
NOT_VALID = r"not a valid PLC \(\d+ problems?; `qualmesh info` lists them\): nothing meshed, nothing written"

# ---------------------------------------------------------------------------------------------------------------
# 1. Invalid PLCs: `mesh` gives exit 2 with the defect as `info` names it; `info` is run on the same file with the
# same pattern, so the two cannot drift apart.
INVALID_PLCS = [
    ("open-box-off", "open_box.off", r"error\[open-boundary\]: edge \(0, 3\) of facet 0 is on no other facet"),
    ("open-box-stl", "open_box.stl", r"error\[open-boundary\]: edge \(\d+, \d+\) of facet \d+ is on no other facet"),
    ("duplicated-face", "duplicated_face.off",
     r"error\[intersection\]: facets 2 and 6 intersect \(not in a shared vertex or edge\) \(they overlap\)"),
    ("duplicated-face-reversed", "duplicated_face_reversed.off",
     r"error\[intersection\]: facets 2 and 6 intersect .*\(they overlap\)"),
    ("duplicated-internal-facet", "duplicated_internal_facet.poly",
     r"error\[intersection\]: facets 10 and 11 intersect .*\(they overlap\)"),
    ("four-vertex-stl-facet", "four_vertex_facet.stl",
     r"error\[non-planar-facet\]: facet 0 is not planar: vertex 3 is 0\.001 from the facet's plane"),
    ("bowtie-stl-facet", "bowtie_facet.stl", r"error\[intersection\]: segments? .*intersect"),
    ("quad-off-plane-off", "quad_off_plane.off",
     r"error\[non-planar-facet\]: facet 1 is not planar: vertex 7 is 0\.001 from the facet's plane "
     r"\(tolerance 1\.73e-06"),
    ("quad-off-plane-poly", "quad_off_plane.poly",
     r"error\[non-planar-facet\]: facet 1 is not planar: vertex 7 is 0\.001"),
    ("overlapping-cubes", "overlapping_cubes.off",
     r"error\[intersection\]: facets 1 and 8 intersect \(not in a shared vertex or edge\)"),
    ("self-intersecting-stl", "self_intersecting.stl", r"error\[intersection\]: facets 2 and 4 intersect"),
    # a face repeating a vertex or of zero area: refused by the reader with the face's number and line (msg-*)
    ("single-triangle", "single_triangle.off", r"error\[open-boundary\]: edge \(0, 1\) of facet 0 is on no other"),
    ("flat-square", "flat_square.off", r"error\[open-boundary\]: edge \(0, 1\) of facet 0 is on no other facet"),
]
for name, file, pattern in INVALID_PLCS:
    case(f"plc-{name}", ["mesh", "{in}/" + file, "-o", "{out}"], 2, pattern + r"[\s\S]*" + NOT_VALID)
    case(f"plc-{name}-info", ["info", "{in}/" + file], 2, pattern)
# validation comes first: a bad option value is still refused first (parse time), and -v says how long it took
case("plc-open-box-verbose", ["mesh", "{in}/open_box.off", "-o", "{out}", "-v"], 2,
     r"qualmesh: validation: INVALID in [0-9.e-]+ s[\s\S]*error\[open-boundary\]")
case("plc-open-box-bad-option", ["mesh", "{in}/open_box.off", "-o", "{out}", "--omega", "2"], 2,
     r"^--omega: '2' is out of range")
# hole seeds that remove every region: known only once the boundary is meshed; exit 2 and nothing written
case("plc-hole-removes-domain", ["mesh", "{in}/whole_domain_hole.poly", "-o", "{out}"], 2,
     r"error\[empty\]: the hole seed removes every region of the domain, so the mesh would be empty: nothing written")
case("plc-holes-remove-both-regions", ["mesh", "{in}/both_regions_holes.poly", "-o", "{out}"], 2,
     r"error\[empty\]: the 2 hole seeds remove every region of the domain")
case("plc-max-vertices-below-input", ["mesh", BOX, "-o", "{out}", "--max-vertices", "7"], 2,
     r"--max-vertices 7 is below the input's 8 vertices: nothing meshed, nothing written")

# ---------------------------------------------------------------------------------------------------------------
# 2. Numeric options. (option, expected-range text as the message shows it, bad values with the message kind.)
NOT_A_NUMBER = "is not a number"
NAN = r"is not a number \(NaN\)"
NOT_FINITE = "is not finite"
OUT_OF_RANGE = "is out of range"
TOO_SMALL = "is too small to compute with"
COMMON_BAD = [("nan", NAN), ("NaN", NAN), ("-nan", NAN), ("inf", NOT_FINITE), ("-inf", NOT_FINITE),
              ("infinity", NOT_FINITE), ("1e999", NOT_FINITE), ("abc", NOT_A_NUMBER), ("", None),
              ("2x", NOT_A_NUMBER), ("1,5", NOT_A_NUMBER)]
FLOAT_OPTIONS = [
    ("--radius-edge", r">= 1\.1", ["0", "-1", "0.5", "1", "1.09", "-0"]),
    ("--max-edge", r"> 0", ["0", "-1", "-0", "-1e-9"]),
    ("--max-volume", r"> 0", ["0", "-1", "-0", "-1e300"]),
    ("--sliver-angle", r"in \(0, 60\)", ["0", "-1", "60", "70.53", "90", "180"]),
    ("--omega", r"in \(0, 1\)", ["0", "1", "-0.5", "10"]),
    ("--delta", r"in \(0, 0\.5\)", ["0", "0.5", "0.9", "-0.1"]),
    ("--sliver-budget", r"in \[0, 1\]", ["-0.1", "1.5", "-1e-300"]),
    ("--deflection", r"> 0", ["0", "-1"]),
    ("--relative-deflection", r"in \(0, 1\)", ["0", "1", "2", "-0.1"]),
]


def _slug(value):
    return {"": "empty", "-nan": "minus-nan", "-inf": "minus-inf", "-0": "minus-zero"}.get(
        value, re.sub(r"[^A-Za-z0-9.]+", "_", value))


for option, range_text, out_of_range in FLOAT_OPTIONS:
    for value, kind in COMMON_BAD + [(v, OUT_OF_RANGE) for v in out_of_range]:
        case(f"opt{option}-{_slug(value)}", ["mesh", BOX, "-o", "{out}", f"{option}={value}"], 2,
             rf"^{option}: '{re.escape(value)}' {kind}: expected a finite number {range_text}" if value else
             rf"^{option}: 1 required FLOAT:{range_text} missing")  # CLI11 refuses an empty value itself
# the separated form of a negative value, and a value given twice (the last one counts, and is checked)
case("opt--max-edge-minus-one-separate", ["mesh", BOX, "-o", "{out}", "--max-edge", "-1"], 2,
     r"^--max-edge: '-1' is out of range: expected a finite number > 0 \(leave the option out for no limit\)")
case("opt--radius-edge-twice", ["mesh", BOX, "-o", "{out}", "--radius-edge", "2", "--radius-edge", "0.5"], 2,
     r"^--radius-edge: '0\.5' is out of range: expected a finite number >= 1\.1 \(below 1\.1 refinement may not end")
# underflow: a length whose square is 0 would read as "no limit"
case("opt--max-edge-subnormal", ["mesh", BOX, "-o", "{out}", "--max-edge", "1e-320"], 2,
     r"^--max-edge: '1e-320' is too small to compute with: expected a finite number >= 1e-150")
case("opt--max-volume-subnormal", ["mesh", BOX, "-o", "{out}", "--max-volume", "1e-310"], 2,
     r"^--max-volume: '1e-310' is too small to compute with: expected a finite number >= 1e-300")
case("opt--deflection-subnormal", ["mesh", BOX, "-o", "{out}", "--deflection", "1e-200"], 2,
     r"^--deflection: '1e-200' is too small to compute with")
# --max-vertices: a whole number >= 1
for value, kind in [("0", "is out of range"), ("-1", "is not a whole number"), ("1.5", "is not a whole number"),
                    ("1e6", "is not a whole number"), ("abc", "is not a whole number"),
                    ("nan", "is not a whole number"), ("inf", "is not a whole number"),
                    ("0x10", "is not a whole number"), ("99999999999999999999999", "is too large")]:
    case(f"opt--max-vertices-{_slug(value)}", ["mesh", BOX, "-o", "{out}", f"--max-vertices={value}"], 2,
         rf"^--max-vertices: '{re.escape(value)}' {kind}: expected a whole number >= 1")
# an empty, a missing value, an unknown enumeration value
case("opt--max-vertices-empty", ["mesh", BOX, "-o", "{out}", "--max-vertices="], 2,
     r"^--max-vertices: 1 required UINT:>= 1 missing")
case("opt--radius-edge-missing-value", ["mesh", BOX, "-o", "{out}", "--radius-edge"], 2,
     r"--radius-edge: 1 required FLOAT:>= 1\.1 missing")
case("opt--encroaching-bogus", ["mesh", BOX, "-o", "{out}", "--encroaching", "bogus"], 2,
     r"^--encroaching: Check bogus value in \{all->0,steiner->1\}")
# help shows the ranges
case("opt-help-shows-ranges", ["mesh", "--help"], 0, r"^$")

# ---------------------------------------------------------------------------------------------------------------
# The output path: checked at parse time, before the input is read (so a bad input is not even opened).
UNKNOWN_FORMAT = r"^--output: unknown mesh format \(expected [^)]*\): "
for name, path in [("foo", "mesh.foo"), ("txt", "mesh.txt"), ("vtk", "mesh.vtk"), ("stl", "mesh.stl"),
                   ("off", "mesh.off"), ("no-extension", "mesh"), ("trailing-dot", "mesh."),
                   ("face", "mesh.face")]:
    case(f"out-unknown-{name}", ["mesh", BOX, "-o", "{outdir}/" + path], 2,
         UNKNOWN_FORMAT + "'.*" + re.escape(f"/{path}'"))
case("out-unknown-before-reading", ["mesh", "{malformed}/off_nan.off", "-o", "{outdir}/mesh.foo"], 2,
     UNKNOWN_FORMAT)
case("out-unknown-before-validation", ["mesh", "{in}/open_box.off", "-o", "{outdir}/mesh.foo"], 2, UNKNOWN_FORMAT)
case("out-missing-folder", ["mesh", BOX, "-o", "{outdir}/no/such/folder/mesh.vtu"], 2,
     r"^--output: the directory '.*/no/such/folder' does not exist")
case("out-folder-is-a-file", ["mesh", BOX, "-o", "{small}/box.poly/mesh.vtu"], 2,
     r"^--output: '.*/box\.poly' is not a directory")
case("out-is-a-folder", ["mesh", BOX, "-o", "{outdir}/sub.vtu"], 2, r"^--output: '.*/sub\.vtu' is a directory",
     tags=["mkdir:sub.vtu"])

# ---------------------------------------------------------------------------------------------------------------
# The command line itself.
case("usage-no-subcommand", [], 2, r"A subcommand is required")
case("usage-unknown-subcommand", ["meshh", BOX], 2, r"A subcommand is required")
case("usage-no-output", ["mesh", BOX], 2, r"--output is required")
case("usage-no-input", ["mesh", "-o", "{out}"], 2, r"input is required")
case("usage-unknown-option", ["mesh", BOX, "-o", "{out}", "--bogus"], 2,
     r"The following argument was not expected: --bogus")
case("usage-missing-input-file", ["mesh", "{outdir}/missing.off", "-o", "{out}"], 2,
     r"missing\.off: error\[io\]: cannot open file: No such file or directory")
case("usage-unknown-input-format", ["mesh", "{small}/box.poly.xyz", "-o", "{out}"], 2,
     r"error\[unsupported\]: unknown input format")
case("usage-input-is-a-folder", ["mesh", "{small}", "-o", "{out}"], 2, r"error\[unsupported\]: unknown input format")

# ---------------------------------------------------------------------------------------------------------------
# Malformed files: the readers' corpus, now through `mesh` (file, line and message on stderr, exit 2).


def _malformed_cases():
    table = MALFORMED_DIR / "EXPECTED.tsv"
    if not table.exists():
        return
    for line in table.read_text().splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        file, code, message, line_no = line.split("\t")
        where = re.escape(file) + (f":{line_no}" if line_no != "0" else r"(:\d+)?")  # 0: line not checked
        case(f"read-{file}", ["mesh", "{malformed}/" + file, "-o", "{out}"], 2,
             rf"{where}: error\[{re.escape(code)}\]: .*{re.escape(message)}")


_malformed_cases()

# ---------------------------------------------------------------------------------------------------------------
# What works: a mesh is written, exit 0, stderr empty.
for name, path in [("cube-off", "{in}/cube.off"), ("cube-stl", "{in}/cube.stl"),
                   ("cube-quads-stl", "{in}/cube_quads.stl"), ("two-cubes-internal-facet", "{in}/two_cubes.poly"),
                   ("one-of-two-regions-holed", "{in}/one_of_two_holes.poly"),
                   ("hole-seed-outside", "{in}/hole_outside.poly"), ("tet", "{in}/tet.off"),
                   ("duplicate-unused-vertex", "{in}/duplicate_vertex.off"),
                   ("cube-offset-1e3", "{in}/cube_offset_1e3.off"), ("cube-scaled-1e-3", "{in}/cube_scaled_1e-3.off"),
                   ("box-poly", "{small}/box.poly"), ("box-mesh", "{small}/box.mesh"), ("box-obj", "{small}/box.obj"),
                   ("box-stl", "{small}/box.stl"), ("box-binary-stl", "{small}/box_binary.stl"),
                   ("box-hole-off", "{small}/box_hole.off")]:
    case(f"ok-{name}", ["mesh", path, "-o", "{out}"], 0, r"^$")
for option, value in [("--radius-edge", "1.1"), ("--radius-edge", "1e300"), ("--max-edge", "0.5"),
                      ("--max-volume", "0.01"), ("--max-vertices", "8"), ("--sliver-angle", "59.9"),
                      ("--sliver-angle", "1e-9"), ("--omega", "0.99"), ("--delta", "0.49"), ("--sliver-budget", "0"),
                      ("--sliver-budget", "1"), ("--deflection", "0.01"),
                      ("--relative-deflection", "0.5"), ("--encroaching", "steiner"), ("--encroaching", "ALL")]:
    case(f"ok{option}-{_slug(value)}", ["mesh", BOX, "-o", "{out}", option, value], 0, r"^$")
for ext in ["vtu", "VTU", "msh", "mesh", "inp", "node", "ele"]:
    case(f"ok-out-{ext}", ["mesh", BOX, "-o", "{outdir}/mesh." + ext], 0, r"^$")
case("ok-info-cube", ["info", "{in}/cube.off"], 0, r"^$")

# ---------------------------------------------------------------------------------------------------------------
# far-*: models far from the origin (issue 18 item 5). `check` judges in a frame centred on the input's bounding
# box, with a tolerance of the model's size plus a few ulps of its position: the cube at 1e9 or 1e15 checks clean
# (it "enclosed 0" before), and a vertex 1e-5 off the input at 1e9 is still found (exit 3).
for name in ["1e9", "1e15", "minus_1e15"]:
    case(f"far-check-cube-{name}", ["check", f"{{in}}/cube_mesh_{name}.node", "--ref", f"{{in}}/cube_offset_{name}.off"],
         0, r"^$")
    case(f"far-mesh-cube-{name}", ["mesh", f"{{in}}/cube_offset_{name}.off", "-o", "{out}"], 0, r"^$")
# ---------------------------------------------------------------------------------------------------------------
# limit-*: resource limits (issue 18 item 3), exit 4 and nothing written unless --allow-partial.
RESOURCE = r"error\[resource\]: "
case("limit-max-edge-1e-4-refused-at-once", ["mesh", "{in}/cube.off", "-o", "{out}", "--max-edge", "1e-4"], 4,
     RESOURCE + r"the size field asks for about 3\.3e\+13 tets \(about 5\.5e\+12 vertices\), about 7\.7e\+06 GB needed, "
     r"over the memory budget of [0-9.e+]+ GB \(--max-memory, default 80% of the RAM\): nothing meshed, nothing written",
     timeout=5)
# (--max-memory given, so that the case does not depend on the machine's RAM: the default, 80% of 24 GB, refuses too.)
case("limit-thin-slab-refused-by-feature-size", ["mesh", "{in}/slab_1e-4.off", "-o", "{out}", "--max-memory", "16000"], 4,
     RESOURCE + r"the input's local feature size \(its thinnest parts\) asks for at least about 1e\+08 tets \(about "
     r"1\.7e\+07 vertices\), about 2[0-9] GB needed, over the memory budget of 16 GB \(--max-memory, default 80% "
     r"of the RAM\): nothing meshed, nothing written", timeout=5)
case("limit-nested-cubes-warned-then-stopped", ["mesh", "{in}/nested_100_cubes.off", "-o", "{out}", "--time-limit", "1"],
     4, r"warning: the input's local feature size \(its thinnest parts\) asks for at least about [0-9.]+e\+07 tets, about "
     r"[0-9.]+ GB: this takes a while \(--time-limit and --max-memory bound it\)\n.*" + RESOURCE +
     r"the time limit \(--time-limit 1 s\) stopped meshing", timeout=15)
case("limit-max-volume-refused", ["mesh", "{in}/cube.off", "-o", "{out}", "--max-volume", "1e-12"], 4,
     RESOURCE + r"the size field asks for about 2e\+12 tets", timeout=5)
case("limit-max-memory-estimate", ["mesh", "{in}/cube.off", "-o", "{out}", "--max-edge", "0.01", "--max-memory", "1000"],
     4, RESOURCE + r"the size field asks for about 3\.3e\+07 tets .*about 7\.7 GB needed, over the memory budget of 0\.98 GB", timeout=5)
case("limit-time", ["mesh", "{in}/cube.off", "-o", "{out}", "--max-edge", "0.02", "--time-limit", "0.2"], 4,
     RESOURCE + r"the time limit \(--time-limit 0\.2 s\) stopped meshing at \d+ vertices, \d+ tets: nothing written "
     r"\(--allow-partial writes the partial mesh\)", timeout=10)
case("limit-time-initial-stage", ["mesh", "{in}/prism_2000.off", "-o", "{out}", "--time-limit", "0.2"], 4,
     RESOURCE + r"the time limit \(--time-limit 0\.2 s\) stopped meshing before the input vertices were triangulated: "
     r"nothing written", timeout=10)
case("limit-max-vertices", ["mesh", "{in}/cube.off", "-o", "{out}", "--max-edge", "0.05", "--max-vertices", "100"], 4,
     RESOURCE + r"the vertex limit \(--max-vertices 100\) stopped meshing at 100 vertices, \d+ tets: nothing written")
case("limit-max-vertices-allow-partial", ["mesh", "{in}/cube.off", "-o", "{out}", "--max-edge", "0.05", "--max-vertices",
                                          "100", "--allow-partial"], 4,
     RESOURCE + r"the vertex limit \(--max-vertices 100\) stopped meshing at 100 vertices, \d+ tets: the partial mesh "
     r"is written \(--allow-partial\)", tags=["writes"])
case("limit-time-allow-partial", ["mesh", "{in}/cube.off", "-o", "{out}", "--max-edge", "0.02", "--time-limit", "0.2",
                                  "--allow-partial"], 4, RESOURCE + r"the time limit .*the partial mesh is written",
     tags=["writes"], timeout=10)
for option, range_text, values in [("--time-limit", r"> 0 \(seconds; leave the option out for no limit\)",
                                    ["0", "-1", "-0"]),
                                   ("--max-memory", r">= 16 \(MB; default 80% of the RAM\)", ["0", "1", "15.9", "-5"])]:
    for value, kind in [(v, OUT_OF_RANGE) for v in values] + [("nan", NAN), ("inf", NOT_FINITE), ("abc", NOT_A_NUMBER)]:
        case(f"limit-opt{option}-{_slug(value)}", ["mesh", BOX, "-o", "{out}", f"{option}={value}"], 2,
             rf"^{option}: '{re.escape(value)}' {kind}: expected a finite number" +
             (" " + range_text if kind == OUT_OF_RANGE else ""))
# Inputs that are not regular files (created in the output folder by the runner's tags): refused at once by name.
NOT_REGULAR = [("fifo", "in.off", "mkfifo:in.off", r"is a FIFO \(named pipe\), not a regular file"),
               ("dev-zero-symlink", "zero.off", "symlink:zero.off=/dev/zero",
                r"is a character device \(such as /dev/zero\), not a regular file \(a symbolic link to /dev/zero\)"),
               ("directory", "dir.off", "mkdir:dir.off", r"is a directory, not a file")]
for name, file, tag, pattern in NOT_REGULAR:
    for command in (["mesh", "{outdir}/" + file, "-o", "{out}"], ["info", "{outdir}/" + file]):
        case(f"limit-input-{name}-{command[0]}", command, 2, re.escape(file) + r": error\[io\]: " + pattern,
             tags=[tag], timeout=5)
    mesh_file = file.replace(".off", ".vtu")
    case(f"limit-input-{name}-check", ["check", "{outdir}/" + mesh_file], 2,
         re.escape(mesh_file) + r": error\[io\]: " + pattern, tags=[tag.replace(".off", ".vtu")], timeout=5)
case("ok-limits-generous", ["mesh", BOX, "-o", "{out}", "--time-limit", "60", "--max-memory", "2000"], 0, r"^$")

case("far-check-cube-1e9-vertex-off", ["check", "{in}/cube_mesh_1e9_bent.node", "--ref", "{in}/cube_offset_1e9.off"],
     3, r"")

# ---------------------------------------------------------------------------------------------------------------
# out-atomic-*, out-signal-*: output lands whole or not at all (issue 18 item 4). The TetGen set (.node .ele .face)
# and the Elmer directory are written to temporaries and renamed together; a failure leaves the old files exactly as
# they were (tag file:, checked by the runner), and SIGINT, SIGTERM, SIGHUP during the write leave no "*.tmp-*"
# (the process ends by the signal: exit -N here, 128 + N in a shell). SIGXFSZ (`ulimit -f`) makes the write fail:
# exit 4, a resource limit. Killing qualmesh while `openscad` renders kills openscad and removes its folder.
OLD_SET = ["file:mesh.node=old node", "file:mesh.ele=old ele", "file:mesh.face=old face"]
FILE_SIZE = r"error\[io\]: write failed: the file size limit \(ulimit -f\) was reached"
case("out-atomic-tetgen-face-is-a-folder", ["convert", "{in}/small_mesh.node", "{outdir}/mesh.node"], 2,
     r"mesh\.face: error\[io\]: is a directory: nothing written", tags=["file:mesh.node=old node",
                                                                        "file:mesh.ele=old ele", "mkdir:mesh.face"])
case("out-atomic-tetgen-file-size-limit", ["convert", "{in}/grid.node", "{outdir}/mesh.node"], 4,
     r"mesh\.(node|ele|face): " + FILE_SIZE, tags=OLD_SET + ["fsize:200000"])
case("out-atomic-tetgen-file-size-limit-on-ele", ["convert", "{in}/grid.node", "{outdir}/mesh.node"], 4,
     r"mesh\.ele: " + FILE_SIZE, tags=OLD_SET + ["fsize:2000000"])  # .node fits (about 1 MB), .ele does not
case("out-atomic-tetgen-replaces-old-set", ["convert", "{in}/small_mesh.node", "{outdir}/mesh.node"], 0, r"^$",
     tags=OLD_SET + ["replaces"])
case("out-atomic-mesh-tetgen-file-size-limit", ["mesh", "{in}/cube.off", "-o", "{outdir}/mesh.node",
                                                "--max-edge", "0.1"], 4, FILE_SIZE, tags=OLD_SET + ["fsize:20000"])
case("out-atomic-vtu-file-size-limit", ["convert", "{in}/grid.node", "{outdir}/mesh.vtu"], 4, r"mesh\.vtu: " + FILE_SIZE,
     tags=["file:mesh.vtu=old vtu", "fsize:100000"])
case("out-atomic-elmer-file-size-limit", ["convert", "{in}/grid.node", "{outdir}/mesh.elmer"], 4,
     r"mesh\.elmer: error\[io\]: mesh\.(nodes|elements|boundary): write failed: the file size limit",
     tags=["file:mesh.elmer/mesh.header=old header", "file:mesh.elmer/mesh.nodes=old nodes", "fsize:100000"])
case("out-atomic-elmer-replaces-old-directory", ["convert", "{in}/small_mesh.node", "{outdir}/mesh.elmer"], 0, r"^$",
     tags=["file:mesh.elmer/mesh.header=old header", "replaces"])
case("out-atomic-elmer-mesh-replaces-old-directory", ["mesh", BOX, "-o", "{outdir}/mesh.elmer"], 0, r"^$",
     tags=["file:mesh.elmer/mesh.header=old header", "replaces"])
case("out-atomic-elmer-over-a-file", ["convert", "{in}/small_mesh.node", "{outdir}/mesh.elmer"], 2,
     r"mesh\.elmer: error\[io\]: exists and is not a directory", tags=["file:mesh.elmer=a file"])
for sig, code in [("INT", -2), ("TERM", -15), ("HUP", -1)]:
    case(f"out-signal-{sig.lower()}-vtu", ["convert", "{in}/grid.node", "{outdir}/mesh.vtu"], code, r"^$",
         tags=[f"signal:{sig}", "file:mesh.vtu=old vtu"])
    case(f"out-signal-{sig.lower()}-tetgen", ["convert", "{in}/grid.node", "{outdir}/mesh.node"], code, r"^$",
         tags=[f"signal:{sig}"] + OLD_SET)
    case(f"out-signal-{sig.lower()}-elmer", ["convert", "{in}/grid.node", "{outdir}/mesh.elmer"], code, r"^$",
         tags=[f"signal:{sig}", "file:mesh.elmer/mesh.header=old header"])
case("out-signal-term-msh", ["convert", "{in}/grid.node", "{outdir}/mesh.msh"], -15, r"^$", tags=["signal:TERM"])
case("out-signal-term-inp", ["convert", "{in}/grid.node", "{outdir}/mesh.inp"], -15, r"^$", tags=["signal:TERM"])
for sig, code in [("TERM", -15), ("INT", -2)]:
    case(f"out-signal-{sig.lower()}-during-openscad", ["mesh", "{in}/slow.scad", "-o", "{out}"], code, r"^$",
         tags=[f"scad-signal:{sig}", "needs:openscad"], timeout=60)

# ---------------------------------------------------------------------------------------------------------------
# msg-*: unclear messages made clear (issue 18 item 7).
# A UTF-8 byte order mark and CR-only or CR LF line ends: read as any text file (the OBJ with a mark failed, CR-only
# files gave "absurd count").
for ext in ["obj", "off", "stl", "poly"]:
    case(f"msg-bom-{ext}", ["mesh", f"{{in}}/bom.{ext}", "-o", "{out}"], 0, r"^$")
    case(f"msg-cr-only-{ext}", ["mesh", f"{{in}}/cr_only.{ext}", "-o", "{out}"], 0, r"^$")
    case(f"msg-crlf-{ext}", ["mesh", f"{{in}}/crlf.{ext}", "-o", "{out}"], 0, r"^$")
case("msg-cr-only-line-numbers", ["mesh", "{in}/cr_only_bad_vertex.off", "-o", "{out}"], 2,
     r"cr_only_bad_vertex\.off:5: error\[parse\]: expected a number for the z coordinate of vertex 2, got 'zz'")
case("msg-bom-check-mesh", ["check", "{outdir}/bom.node"], 0, r"^$",
     tags=["file:bom.node=\ufeff4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n",
           "file:bom.ele=\ufeff1 4 0\n1 1 2 3 4\n"])
# A directory: named as one (it was "the file is empty"), also for CAD inputs.
case("msg-directory-stl", ["mesh", "{outdir}/dir.stl", "-o", "{out}"], 2,
     r"dir\.stl: error\[io\]: is a directory, not a file", tags=["mkdir:dir.stl"])
case("msg-directory-step", ["mesh", "{outdir}/dir.step", "-o", "{out}"], 2,
     r"dir\.step: error\[io\]: is a directory, not a file", tags=["mkdir:dir.step"])
case("msg-fifo-step", ["info", "{outdir}/in.step"], 2, r"in\.step: error\[io\]: is a FIFO \(named pipe\)",
     tags=["mkfifo:in.step"], timeout=5)
case("msg-directory-scad", ["mesh", "{outdir}/dir.scad", "-o", "{out}"], 2,
     r"dir\.scad: error\[io\]: is a directory, not a file", tags=["mkdir:dir.scad"])
# Random bytes: quoted as \xNN (the runner refuses any raw control or non-UTF-8 byte on stderr).
RAW = r"\\x[0-9a-f]{2}"
for file, pattern in [("random_bytes.obj", r"random_bytes\.obj:1: error\[parse\]: expected a number for the x "
                                           r"coordinate of vertex 1, got '" + RAW),
                      ("random_bytes.off", r"random_bytes\.off:\d+: error\[parse\]: .*" + RAW),
                      ("random_bytes.stl", r"random_bytes\.stl:\d+: error\[parse\]: .*" + RAW)]:
    case(f"msg-random-bytes-{file.split('.')[1]}", ["mesh", "{in}/" + file, "-o", "{out}"], 2, pattern)
for file in ["random_bytes.inp", "random_bytes.msh", "random_bytes.mesh"]:
    case(f"msg-random-bytes-check-{file.split('.')[1]}", ["check", "{in}/" + file], 2, r"error\[(parse|unsupported)\]")
# Degenerate faces: named by the face number as the file gives it, its line and corners (it was the merged facet id).
DEGENERATE = [("repeated-vertex-face", "degenerate_facet.off",
               r"degenerate_facet\.off:17: error\[degenerate-facet\]: face 6 repeats the vertex at \(0, 0, 0\) "
               r"\(its corners: \(0, 0, 0\), \(1, 0, 0\), \(1, 1, 0\), \(0, 1, 0\), \(0, 0, 0\)\)"),
              ("collinear-triangle-face", "collinear_triangle.off",
               r"collinear_triangle\.off:17: error\[degenerate-facet\]: face 5 has zero area: its corners "
               r"\(1, 0, 0\), \(0, 0, 0\), \(0\.5, 0, 0\) are collinear; it is not repaired because no single "
               r"face holds its long edge the other way round")]
# Degenerate triangles that have an exact repair are repaired, as TetGen meshes such files, and the summary says so.
REPAIRED = [("repaired-repeated-vertex", "repeated_vertex_triangle.off",
             r"source: +repaired: 1 triangle\(s\) repeating a vertex dropped, 0 collinear .*; face 6 \(line 17\) "
             r"repeats a vertex: dropped"),
            ("repaired-collinear", "t_junction_triangle.off",
             r"source: +repaired: 0 triangle\(s\) repeating a vertex dropped, 1 collinear .*; face 6 \(line 18\) "
             r"has collinear corners: dropped, and face 2 \(line 14\) across its long edge split at its middle "
             r"corner \(0\.5, 0, 0\)"),
            ("repaired-collinear-stl", "t_junction_triangle.stl",
             r"source: +repaired: 0 triangle\(s\) repeating a vertex dropped, 1 collinear .*; facet 14 \(line "
             r"\d+\) has collinear corners: dropped, and facet 3 \(line \d+\) across its long edge")]
for name, file, pattern in REPAIRED:
    case(f"msg-{name}", ["mesh", "{in}/" + file, "-o", "{out}"], 0, r"^$", stdout=pattern)
    case(f"msg-{name}-info", ["info", "{in}/" + file], 0, r"^$", stdout=pattern)
for name, file, pattern in DEGENERATE:
    case(f"msg-{name}", ["mesh", "{in}/" + file, "-o", "{out}"], 2, pattern)
    case(f"msg-{name}-info", ["info", "{in}/" + file], 2, pattern)
# Coordinates whose powers overflow or underflow: said so (they were "encloses no area" or "has zero area").
OVERFLOW = r"error\[non-finite\]: the vertex at \([^)]*\) is too far out to compute with \(overflow"
UNDERFLOW = r"error\[non-finite\]: the model spans only [0-9.e+-]+ .*too small to compute with \(underflow"
for name, pattern in [("1e308", OVERFLOW), ("1e100", OVERFLOW), ("minus_1e80", OVERFLOW), ("1e-300", UNDERFLOW),
                      ("1e-100", UNDERFLOW)]:
    case(f"msg-scale-{name.replace('_', '-')}", ["mesh", f"{{in}}/cube_scaled_{name}.off", "-o", "{out}"], 2, pattern)
    case(f"msg-scale-{name.replace('_', '-')}-info", ["info", f"{{in}}/cube_scaled_{name}.off"], 2, pattern)
case("msg-scale-offset-1e75", ["mesh", "{in}/cube_offset_1e75.off", "-o", "{out}"], 2, OVERFLOW)
case("ok-scale-1e60", ["mesh", "{in}/cube_scaled_1e60.off", "-o", "{out}"], 0, r"^$")
case("ok-scale-1e-60", ["mesh", "{in}/cube_scaled_1e-60.off", "-o", "{out}"], 0, r"^$")
# An empty .scad: said so (it was "Geometries in cache: 1").
case("msg-scad-empty", ["mesh", "{in}/empty.scad", "-o", "{out}"], 2,
     r"empty\.scad: error\[empty\]: the file is empty: it describes no object")
case("msg-scad-blank", ["info", "{in}/blank.scad"], 2, r"blank\.scad: error\[empty\]: the file is empty")
case("msg-scad-nothing-drawn", ["mesh", "{in}/comment_only.scad", "-o", "{out}"], 2,
     r"comment_only\.scad: error\[empty\]: the file describes no object \(OpenSCAD: \"Current top level object is "
     r"empty\.\"\)", tags=["needs:openscad"], timeout=60)
# --sewing-tolerance, which the "stays open" message suggests, exists and is range-checked.
for value, kind in [("0", OUT_OF_RANGE), ("-1", OUT_OF_RANGE), ("nan", NAN), ("inf", NOT_FINITE), ("abc", NOT_A_NUMBER)]:
    case(f"opt--sewing-tolerance-{_slug(value)}", ["mesh", BOX, "-o", "{out}", f"--sewing-tolerance={value}"], 2,
         rf"^--sewing-tolerance: '{re.escape(value)}' {kind}: expected a finite number" +
         (r" > 0 \(model units; leave the option out for the automatic tolerance\)" if kind == OUT_OF_RANGE else ""))
case("ok-sewing-tolerance-cad", ["info", "{shared}/data/cad/part.step", "--sewing-tolerance", "1e-3"], 0, r"^$",
     tags=["needs:shared"], timeout=60)
# --coplanar-tolerance, which the reader's note suggests, is range-checked in every command that reads an input.
for command, value, kind in [("mesh", "2e-6", OUT_OF_RANGE), ("info", "-1", OUT_OF_RANGE), ("convert", "nan", NAN),
                             ("mesh", "inf", NOT_FINITE), ("check", "abc", NOT_A_NUMBER)]:
    argv = {"mesh": ["mesh", BOX, "-o", "{out}"], "info": ["info", BOX], "convert": ["convert", BOX, "{out}.poly"],
            "check": ["check", "{in}/fuzz_region_attribute.node", "--ref", BOX]}[command]
    case(f"opt--coplanar-tolerance-{command}-{_slug(value)}", argv + [f"--coplanar-tolerance={value}"], 2,
         rf"^--coplanar-tolerance: '{re.escape(value)}' {kind}: expected a finite number in \[0, 1e-06\]" +
         (r" \(a fraction of the bounding-box diagonal" if kind == OUT_OF_RANGE else ""))
case("ok-coplanar-tolerance", ["mesh", BOX, "-o", "{out}", "--coplanar-tolerance", "1e-6"], 0, r"^$")
# Fuzzing findings (tests/fuzz/regressions), each by its exact input: a region attribute beyond int (UB before).
case("fuzz-tetgen-region-attribute-beyond-int", ["check", "{in}/fuzz_region_attribute.node"], 2,
     r"fuzz_region_attribute\.ele:\d+: error\[parse\]: the region attribute of tetrahedron \d+ \([0-9.e+]+\) is "
     r"outside -2e9\.\.2e9")
case("fuzz-tetgen-vertex-index-overflow", ["check", "{in}/fuzz_vertex_index.node"], 2,
     r"fuzz_vertex_index\.ele:2: error\[index-out-of-range\]: vertex index -9223372036854775808 out of range")
case("fuzz-vtu-offset-beyond-size-t", ["check", "{in}/fuzz_offset_beyond_size_t.vtu"], 2,
     r"fuzz_offset_beyond_size_t\.vtu:\d+: error\[parse\]: bad offsets: cell 7 ends at 3\.1e\+78, outside 27\.\.60 or not "
     r"a whole number")
case("fuzz-inp-set-copied-into-itself", ["check", "{in}/fuzz_set_copied_into_itself.inp"], 2,
     r"fuzz_set_copied_into_itself\.inp:4: error\[index-out-of-range\]: node set Face3 names missing node 1 \(a set "
     r"names nodes defined above it\)", timeout=10)
case("fuzz-medit-vertex-count-beyond-file", ["check", "{in}/fuzz_vertex_count.mesh"], 2,
     r"fuzz_vertex_count\.mesh:\d+: error\[parse\]: absurd the number of vertices: 999999999, but only \d+ bytes")
