# A whole FEM analysis in FreeCADCmd, meshed by QualMesh: the cantilever of examples/cantilever from its STEP file.
#
#   freecadcmd examples/freecad_headless.py
#
# A 100 x 10 x 10 mm steel beam (E = 210000 MPa, nu = 0.3) fixed on Face1 (x = 0), 1000 N shear in -y on Face2
# (x = 100): QualMesh second-order mesh, FreeCAD's CalculiX writer, ccx, and the mean tip deflection over Face2's
# nodes (about 1.90 mm; fine second-order meshes converge to 1.906 mm, Euler-Bernoulli gives 1.905 mm).
# Needs the addon (installed in FreeCAD's Mod folder, or found beside this file in ../freecad_module), the qualmesh
# executable (QUALMESH_EXE, the preference, or PATH) and ccx. Settings through the environment:
#   QUALMESH_EXAMPLE_STEP      the STEP file (default: cantilever/beam.step beside this script)
#   QUALMESH_EXAMPLE_MAX_SIZE  CharacteristicLengthMax in mm (default 8)
#   QUALMESH_EXAMPLE_WORKDIR   where the deck and results go (default: a new temporary folder)
#   QUALMESH_EXAMPLE_RESULT    a JSON file to write the figures to (optional)
# freecadcmd exits 0 even when a script raises, so this one exits 1 itself on any failure.

import json
import os
import sys
import tempfile
import time
import traceback

HERE = os.path.dirname(os.path.abspath(__file__)) if "__file__" in globals() else os.getcwd()


def build_analysis(doc, step_path, max_size):
    import ObjectsFem
    import Part
    import qualmesh_fem

    beam = doc.addObject("Part::Feature", "Beam")
    beam.Shape = Part.read(step_path)
    doc.recompute()

    analysis = ObjectsFem.makeAnalysis(doc, "Analysis")
    analysis.addObject(ObjectsFem.makeSolverCalculixCcxTools(doc, "CalculiX"))
    material = ObjectsFem.makeMaterialSolid(doc, "Steel")
    mat = material.Material
    mat.update({"Name": "Steel", "YoungsModulus": "210000 MPa", "PoissonRatio": "0.30"})
    material.Material = mat
    analysis.addObject(material)

    fixed = ObjectsFem.makeConstraintFixed(doc, "Fixed")
    fixed.References = [(beam, "Face1")]
    analysis.addObject(fixed)
    force = ObjectsFem.makeConstraintForce(doc, "TipForce")
    force.References = [(beam, "Face2")]
    force.Force = 1000.0
    # Direction: an edge of the beam along y; reversed if it points to +y.
    y_edges = [i for i, e in enumerate(beam.Shape.Edges, 1)
               if abs(abs((e.Vertexes[1].Point - e.Vertexes[0].Point).normalize().y) - 1.0) < 1e-9]
    force.Direction = (beam, ["Edge{}".format(y_edges[0])])
    doc.recompute()
    if force.DirectionVector.y > 0:
        force.Reversed = not force.Reversed
        doc.recompute()
    analysis.addObject(force)

    t0 = time.time()
    mesh = qualmesh_fem.add_mesh_to_analysis(analysis, beam, max_size=max_size, order=2,
                                             log=lambda line: None)
    mesh_s = time.time() - t0
    return analysis, beam, force, mesh, mesh_s


def solve(analysis, workdir):
    from femtools import ccxtools
    solver = [o for o in analysis.Group if o.isDerivedFrom("Fem::FemSolverObjectPython")][0]
    fea = ccxtools.FemToolsCcx(analysis, solver)
    fea.update_objects()
    os.makedirs(workdir, exist_ok=True)  # FreeCAD 0.20's setup_working_dir(create=True) does not create it
    fea.setup_working_dir(workdir, create=True)
    message = fea.check_prerequisites()
    if message:
        raise RuntimeError("FEM prerequisites: " + message)
    fea.write_inp_file()
    fea.setup_ccx()
    fea.ccx_run()
    fea.load_results()
    results = [o for o in analysis.Group if o.isDerivedFrom("Fem::FemResultObject")]
    if not results:
        raise RuntimeError("ccx gave no results (see {})".format(workdir))
    return fea.inp_file_name, results[-1]


def mean_tip_deflection(mesh_obj, result, force):
    """Mean displacement of Face2's nodes along the force direction (mm)."""
    import qualmesh_fem
    tip_nodes = set(qualmesh_fem.group_elements(mesh_obj.FemMesh, "Face2", "Node"))
    direction = force.DirectionVector  # Reversed is already applied to it
    values = [d.dot(direction) for n, d in zip(result.NodeNumbers, result.DisplacementVectors) if n in tip_nodes]
    return sum(values) / len(values), len(values)


def main():
    try:
        import qualmesh_fem  # noqa: F401 (installed addon)
    except ImportError:
        sys.path.insert(0, os.path.join(HERE, "..", "freecad_module"))
    import FreeCAD

    step_path = os.environ.get("QUALMESH_EXAMPLE_STEP", os.path.join(HERE, "cantilever", "beam.step"))
    max_size = float(os.environ.get("QUALMESH_EXAMPLE_MAX_SIZE", "8"))
    workdir = os.environ.get("QUALMESH_EXAMPLE_WORKDIR") or tempfile.mkdtemp(prefix="qualmesh_cantilever_")

    doc = FreeCAD.newDocument("Cantilever")
    analysis, beam, force, mesh, mesh_s = build_analysis(doc, step_path, max_size)
    t0 = time.time()
    inp, result = solve(analysis, workdir)
    solve_s = time.time() - t0
    deflection, tip_nodes = mean_tip_deflection(mesh, result, force)
    doc.saveAs(os.path.join(workdir, "cantilever.FCStd"))

    figures = {"nodes": mesh.Nodes, "tetrahedra": mesh.Tetrahedra, "min_dihedral_deg": mesh.MinDihedralAngle.Value,
               "max_size_mm": max_size, "tip_nodes": tip_nodes, "mean_tip_deflection_mm": deflection,
               "mesh_s": mesh_s, "write_and_solve_s": solve_s, "deck": inp}
    print("\nQualMesh mesh: {} nodes, {} tetrahedra (C3D10), min dihedral {:.2f} deg, {:.2f} s".format(
        mesh.Nodes, mesh.Tetrahedra, mesh.MinDihedralAngle.Value, mesh_s))
    print("CalculiX deck written by FreeCAD: {} (write + ccx {:.2f} s)".format(inp, solve_s))
    print("mean tip deflection (Face2, {} nodes): {:.4f} mm (converged 1.906 mm)".format(tip_nodes, deflection))
    result_path = os.environ.get("QUALMESH_EXAMPLE_RESULT")
    if result_path:
        with open(result_path, "w") as f:
            json.dump(figures, f, indent=1)


try:
    main()
except Exception:
    traceback.print_exc()
    sys.exit(1)
