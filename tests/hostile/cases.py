"""The hostile-input catalogue of issue 18: what a new user types on the first day, and what `qualmesh` must answer.

Each case is a name, the argv after `qualmesh`, the exact exit code and a regular expression that stderr must match
(re.search; for exit 0 stderr must also be empty). Refused cases (exit != 0) must leave the output folder empty:
no mesh, no temporary file. Placeholders in argv:
  {in}/NAME         a file of inputs.py's INPUTS, written for the run
  {small}/NAME      tests/data/small/NAME
  {malformed}/NAME  tests/data/malformed/NAME (the readers' corpus; EXPECTED.tsv holds its messages)
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
    ("repeated-vertex-facet", "degenerate_facet.off",
     r"error\[degenerate-facet\]: polygon 0 of facet 6 repeats vertex 0"),
    ("collinear-triangle", "collinear_triangle.off",
     r"error\[degenerate-facet\]: polygon 0 of facet 5 has zero area \(all its vertices are collinear\)"),
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
                      ("--sliver-angle", "1e-9"), ("--omega", "0.99"), ("--delta", "0.49"), ("--deflection", "0.01"),
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
