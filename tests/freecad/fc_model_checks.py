# Run by `freecadcmd` (not by pytest): meshes one model through the QualMesh FEM addon and writes the facts the
# pytest driver (tests/python/test_freecad_headless.py) asserts, as JSON.
#
# Environment: QUALMESH_FC_CASE (box | cylinder | step | stacked_beam), QUALMESH_FC_INPUT (the STEP or FCStd file),
# QUALMESH_FC_MAX_SIZE (mm), QUALMESH_FC_WORKDIR (scratch folder), QUALMESH_FC_RESULT (the JSON to write),
# QUALMESH_FC_UNV (optional: the same model meshed by the CLI as .unv, to compare element by element).
# freecadcmd exits 0 even when a script raises, so any exception is caught, written and turned into exit status 1.

import json
import os
import sys
import time
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fchelpers import canonical_tets, mesh_groups, tet_facts  # noqa: E402

RESULT = {"case": os.environ.get("QUALMESH_FC_CASE"), "errors": []}


def _write_result():
    with open(os.environ["QUALMESH_FC_RESULT"], "w") as f:
        json.dump(RESULT, f, indent=1, sort_keys=True)


def face_checks(femmesh, shape, group_elements):
    """For every face of the shape: our Face<i> node group against FEM's geometric search getNodesByFace. Of the
    nodes the search misses, how many lie outside the face's own bounding box (which the search starts from, and
    which OpenCASCADE does not always make around the whole surface: part.step's Face23 bulges 0.007 mm past it),
    and the largest distance of a missed node from the face."""
    import Part
    faces = []
    for i, face in enumerate(shape.Faces, 1):
        ours = set(group_elements(femmesh, "Face{}".format(i), "Node") or ())
        found = set(femmesh.getNodesByFace(face))
        box = face.BoundBox
        box.enlarge(face.Tolerance)
        missed = [femmesh.getNodeById(n) for n in sorted(ours - found)]
        faces.append({"name": "Face{}".format(i), "surface": type(face.Surface).__name__,
                      "planar": type(face.Surface).__name__ == "Plane", "ours": len(ours), "found": len(found),
                      "missing": len(missed), "extra": len(found - ours),
                      "missing_outside_box": sum(not box.isInside(p) for p in missed),
                      "missing_max_distance": max([face.distToShape(Part.Vertex(p))[0] for p in missed] or [0.0])})
    return faces


def edge_checks(femmesh, shape, group_elements):
    edges = []
    for i, edge in enumerate(shape.Edges, 1):
        ours = set(group_elements(femmesh, "Edge{}".format(i), "Node") or ())
        found = set(femmesh.getNodesByEdge(edge))
        edges.append({"name": "Edge{}".format(i), "curve": type(edge.Curve).__name__, "ours": len(ours),
                      "found": len(found), "missing": len(ours - found), "extra": len(found - ours)})
    return edges


def constraint_checks(analysis, part, femmesh, group_elements):
    """For every FEM constraint on a face: the Part's face it is (found geometrically when the constraint names
    another object's face, as FEM's own meshtools do) and our group against getNodesByFace of its face."""
    from femtools import geomtools
    checks = []
    for obj in analysis.Group:
        if not obj.isDerivedFrom("Fem::Constraint") or not hasattr(obj, "References"):
            continue
        for ref_obj, names in obj.References:
            for name in names:
                element = ref_obj.Shape.getElement(name)
                if element.ShapeType != "Face":
                    continue
                in_part = name if ref_obj == part else geomtools.find_element_in_shape(part.Shape, element)
                ours = set(group_elements(femmesh, in_part, "Node") or ()) if in_part else set()
                found = set(femmesh.getNodesByFace(element))
                checks.append({"constraint": obj.Name, "reference": "{}.{}".format(ref_obj.Name, name),
                               "part_face": in_part, "planar": type(element.Surface).__name__ == "Plane",
                               "ours": len(ours), "found": len(found), "missing": len(ours - found),
                               "extra": len(found - ours)})
    return checks


def snapshot(doc):
    """What a failed or cancelled run must not change: every object and property value, every mesh's content."""
    state = {}
    for obj in doc.Objects:
        props = {}
        for name in obj.PropertiesList:
            if name in ("FemMesh", "Shape", "Proxy", "ExpressionEngine", "Label2"):
                continue
            try:
                props[name] = repr(getattr(obj, name))
            except Exception as e:
                props[name] = "unreadable: {}".format(e)
        if obj.isDerivedFrom("Fem::FemMeshObject"):
            m = obj.FemMesh
            props["FemMesh"] = (m.NodeCount, m.VolumeCount, m.FaceCount, tuple(mesh_groups(m)),
                                hash(tuple(m.getElementNodes(v) for v in m.Volumes)))
        state[obj.Name] = (obj.TypeId, props)
    return state


def run_ccx(analysis, workdir):
    from femtools import ccxtools
    solver = [o for o in analysis.Group if o.isDerivedFrom("Fem::FemSolverObjectPython")][0]
    fea = ccxtools.FemToolsCcx(analysis, solver)
    fea.update_objects()
    os.makedirs(workdir, exist_ok=True)  # FreeCAD 0.20's setup_working_dir(create=True) does not create it
    fea.setup_working_dir(workdir, create=True)
    message = fea.check_prerequisites()
    if message:
        raise RuntimeError("FEM prerequisites: " + message)
    t0 = time.time()
    fea.write_inp_file()
    write_s = time.time() - t0
    fea.setup_ccx()
    t0 = time.time()
    fea.ccx_run()
    run_s = time.time() - t0
    fea.load_results()
    results = [o for o in analysis.Group if o.isDerivedFrom("Fem::FemResultObject")]
    inp = fea.inp_file_name
    with open(inp) as f:
        deck = f.read()
    return {"inp": inp, "write_s": write_s, "run_s": run_s, "deck_has_c3d10": "C3D10" in deck,
            "results": len(results), "frd": os.path.exists(os.path.splitext(inp)[0] + ".frd"),
            "result_obj": results[-1].Name if results else None}


def setup_static_analysis(doc, part, fixed_face, load_face, pressure=False):
    import ObjectsFem
    analysis = ObjectsFem.makeAnalysis(doc, "Analysis")
    solver = ObjectsFem.makeSolverCalculixCcxTools(doc, "CalculiX")
    analysis.addObject(solver)
    material = ObjectsFem.makeMaterialSolid(doc, "Steel")
    mat = material.Material
    mat.update({"Name": "Steel", "YoungsModulus": "210000 MPa", "PoissonRatio": "0.30"})
    material.Material = mat
    analysis.addObject(material)
    fixed = ObjectsFem.makeConstraintFixed(doc, "ConstraintFixed")
    fixed.References = [(part, fixed_face)]
    analysis.addObject(fixed)
    if pressure:
        load = ObjectsFem.makeConstraintPressure(doc, "ConstraintPressure")
        load.References = [(part, load_face)]
        load.Pressure = 1.0
    else:
        load = ObjectsFem.makeConstraintForce(doc, "ConstraintForce")
        load.References = [(part, load_face)]
        load.Force = 100.0
    analysis.addObject(load)
    return analysis


def main():
    import FreeCAD
    import Part
    import qualmesh_fem
    from qualmesh_fem import group_elements

    case = os.environ["QUALMESH_FC_CASE"]
    workdir = os.environ["QUALMESH_FC_WORKDIR"]
    max_size = float(os.environ.get("QUALMESH_FC_MAX_SIZE", "0"))
    source = os.environ.get("QUALMESH_FC_INPUT", "")

    if case == "stacked_beam":
        doc = FreeCAD.openDocument(source)
        analysis = doc.Analysis
        part = doc.BooleanFragments
        # The analysis needs exactly one mesh: ours replaces the document's Gmsh mesh in it.
        analysis.Group = [o for o in analysis.Group
                          if not o.isDerivedFrom("Fem::FemMeshObject") and not o.isDerivedFrom("Fem::FemResultObject")]
    else:
        doc = FreeCAD.newDocument("QualMeshCheck")
        if case == "box":
            part = doc.addObject("Part::Box", "Box")
            part.Length, part.Width, part.Height = 100, 10, 10
        elif case == "cylinder":
            part = doc.addObject("Part::Cylinder", "Cylinder")
            part.Radius, part.Height = 5, 20
        elif case == "step":
            part = doc.addObject("Part::Feature", "Part")
            part.Shape = Part.read(source)
        else:
            raise ValueError("unknown case " + case)
        doc.recompute()
        planar = [i for i, f in enumerate(part.Shape.Faces, 1) if type(f.Surface).__name__ == "Plane"]
        curved = [i for i, f in enumerate(part.Shape.Faces, 1) if type(f.Surface).__name__ != "Plane"]
        # Box: the cantilever's supports. Others: fixed on a planar face, pressure on a curved one if any.
        load_face = "Face2" if case == "box" else "Face{}".format((curved or planar[1:])[0])
        analysis = setup_static_analysis(doc, part, "Face{}".format(planar[0]), load_face,
                                         pressure=(case != "box"))

    shape = part.Shape
    RESULT["shape"] = {"solids": len(shape.Solids), "faces": len(shape.Faces), "edges": len(shape.Edges),
                       "type": shape.ShapeType}

    # 1. mesh it: object in the analysis, meshed by the tool
    t0 = time.time()
    mesh_obj = qualmesh_fem.add_mesh_to_analysis(analysis, part, max_size=max_size, order=2, create=False)
    tools = qualmesh_fem.QualMeshTools(mesh_obj, analysis)
    result = tools.create_mesh()
    RESULT["create"] = {"status": result.status, "message": result.message, "warnings": result.warnings,
                        "statistics": result.statistics, "timings_s": result.timings_s, "wall_s": time.time() - t0}
    if not result.succeeded:
        raise RuntimeError("create_mesh: " + result.message)
    femmesh = mesh_obj.FemMesh
    RESULT["mesh"] = {"nodes": femmesh.NodeCount, "volumes": femmesh.VolumeCount, "faces": femmesh.FaceCount,
                      "tetra": femmesh.TetraCount, "groups": mesh_groups(femmesh),
                      "object_stats": {"Nodes": mesh_obj.Nodes, "Tetrahedra": mesh_obj.Tetrahedra,
                                       "MinDihedralAngle": mesh_obj.MinDihedralAngle.Value,
                                       "TetsBelow10Deg": mesh_obj.TetsBelow10Deg},
                      "proxy_type": mesh_obj.Proxy.Type, "orientation": tet_facts(femmesh)}

    # 2. our groups against FreeCAD's geometric search
    RESULT["faces"] = face_checks(femmesh, shape, group_elements)
    RESULT["edges"] = edge_checks(femmesh, shape, group_elements)
    RESULT["constraints"] = constraint_checks(analysis, part, femmesh, group_elements)

    # 3. the same mesh read by FreeCAD's own UNV import (the CLI's .unv of the same BREP)
    unv = os.environ.get("QUALMESH_FC_UNV")
    if unv:
        import Fem
        other = Fem.read(unv)
        a, b = canonical_tets(femmesh), canonical_tets(other)
        RESULT["unv_compare"] = {"same_tets": a == b, "ours": len(a), "unv": len(b),
                                 "same_face_node_groups": all(
                                     set(group_elements(femmesh, "Face{}".format(i), "Node") or ()) ==
                                     set(group_elements(other, "Face{}_Nodes".format(i), "Node") or ())
                                     for i in range(1, len(shape.Faces) + 1))}

    # 4. FreeCAD's CalculiX writer and ccx
    RESULT["ccx"] = run_ccx(analysis, os.path.join(workdir, "ccx"))

    # 5. save, reopen: the mesh, its groups, the proxy and the statistics come back
    path = os.path.join(workdir, "saved.FCStd")
    before = {"groups": mesh_groups(femmesh), "nodes": femmesh.NodeCount, "volumes": femmesh.VolumeCount,
              "tets": canonical_tets(femmesh) if femmesh.VolumeCount < 50000 else None,
              "stats": RESULT["mesh"]["object_stats"]}
    name, analysis_name = mesh_obj.Name, analysis.Name
    doc.saveAs(path)
    FreeCAD.closeDocument(doc.Name)
    doc = FreeCAD.openDocument(path)
    mesh_obj = doc.getObject(name)
    reopened = mesh_obj.FemMesh
    RESULT["reopen"] = {
        "same_groups": mesh_groups(reopened) == before["groups"],
        "same_counts": (reopened.NodeCount, reopened.VolumeCount) == (before["nodes"], before["volumes"]),
        "same_tets": before["tets"] is None or canonical_tets(reopened) == before["tets"],
        "proxy_type": getattr(getattr(mesh_obj, "Proxy", None), "Type", None),
        "stats": {"Nodes": mesh_obj.Nodes, "Tetrahedra": mesh_obj.Tetrahedra,
                  "MinDihedralAngle": mesh_obj.MinDihedralAngle.Value, "TetsBelow10Deg": mesh_obj.TetsBelow10Deg},
        "in_analysis": mesh_obj in doc.getObject(analysis_name).Group}

    # 6. a failing run leaves the document as it was
    failures = {}
    state = snapshot(doc)
    os.environ["QUALMESH_EXE"], saved_exe = os.path.join(workdir, "no-such-qualmesh"), os.environ["QUALMESH_EXE"]
    bad = qualmesh_fem.QualMeshTools(mesh_obj).create_mesh()
    os.environ["QUALMESH_EXE"] = saved_exe
    failures["missing_exe"] = {"status": bad.status, "message": bad.message, "unchanged": snapshot(doc) == state}
    fail_exe = os.path.join(workdir, "failing-qualmesh")
    with open(fail_exe, "w") as f:
        f.write("#!/bin/sh\ncase \"$2\" in --help) exec \"$QM_REAL\" \"$@\";; esac\n"
                "echo 'qualmesh: error: simulated failure' >&2\nexit 2\n")
    os.chmod(fail_exe, 0o755)
    os.environ["QM_REAL"] = saved_exe
    os.environ["QUALMESH_EXE"] = fail_exe
    bad = qualmesh_fem.QualMeshTools(mesh_obj).create_mesh()
    os.environ["QUALMESH_EXE"] = saved_exe
    failures["exit_2"] = {"status": bad.status, "message": bad.message, "unchanged": snapshot(doc) == state}
    RESULT["failures"] = failures
    _write_result()


try:
    main()
    _write_result()
except Exception:
    RESULT["errors"].append(traceback.format_exc())
    _write_result()
    sys.stderr.write(traceback.format_exc())
    sys.exit(1)
