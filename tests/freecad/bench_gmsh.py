# Run by `freecadcmd` (a measurement, not a test): FreeCAD's Gmsh mesher (ObjectsFem.makeMeshGmsh + GmshTools)
# against QualMesh (make_mesh_qualmesh + QualMeshTools) on the same Part at the same CharacteristicLengthMax,
# second order, both from a FreeCAD document object through their FEM tools: wall time of create_mesh() (mesher
# and reading into FreeCAD), nodes, tetrahedra, min dihedral angle and tets below 10 degrees (straight-sided tets,
# measured the same way for both). Gmsh runs with FreeCAD's settings (General.NumThreads = cpu count).
#   QUALMESH_SHARED_DIR=../shared freecadcmd tests/freecad/bench_gmsh.py   -> a Markdown table on stdout
import os
import sys
import time
import traceback

import numpy as np

SHARED = os.environ.get("QUALMESH_SHARED_DIR", os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                            "..", "..", "..", "shared"))
MODELS = [  # (label, file, object holding the shape or None for a STEP file, CharacteristicLengthMax mm)
    ("part.step", "data/cad/part.step", None, 10.0),
    ("fcFEM_Spanner.FCStd", "data/cad/fcFEM_Spanner.FCStd", "Body", 5.0),
    ("fcFEM_Stacked_Beam_Example.FCStd", "data/cad/fcFEM_Stacked_Beam_Example.FCStd", "BooleanFragments", 4.0),
]


def quality(femmesh):
    from qualmesh_fem import meshreader
    nodes = femmesh.Nodes
    ids = sorted(nodes)
    index = {n: i for i, n in enumerate(ids)}
    xyz = np.array([[nodes[n].x, nodes[n].y, nodes[n].z] for n in ids])
    tets = np.array([[index[n] for n in femmesh.getElementNodes(v)[:4]] for v in femmesh.Volumes])
    angles = meshreader.dihedral_angles_deg(xyz[tets]).min(axis=1)
    return float(angles.min()), int((angles < 10).sum())


def main():
    import FreeCAD
    import ObjectsFem
    import Part
    import qualmesh_fem
    from femmesh import gmshtools

    rows = []
    for label, relative, holder, clmax in MODELS:
        path = os.path.join(SHARED, relative)
        if holder is None:
            doc = FreeCAD.newDocument("Bench")
            part = doc.addObject("Part::Feature", "Part")
            part.Shape = Part.read(path)
            doc.recompute()
        else:
            doc = FreeCAD.openDocument(path)
            part = doc.getObject(holder)
        for mesher in ("Gmsh", "QualMesh"):
            if mesher == "Gmsh":
                obj = ObjectsFem.makeMeshGmsh(doc, "BenchGmsh")
            else:
                obj = qualmesh_fem.make_mesh_qualmesh(doc, "BenchQualMesh")
            obj.Part = part
            obj.CharacteristicLengthMax = clmax
            obj.ElementOrder = "2nd"
            t = time.time()
            if mesher == "Gmsh":
                error = gmshtools.GmshTools(obj).create_mesh()
            else:
                result = qualmesh_fem.QualMeshTools(obj).create_mesh()
                error = "" if result.succeeded else result.message
            wall = time.time() - t
            m = obj.FemMesh
            min_deg, below_10 = quality(m) if m.VolumeCount else (float("nan"), 0)
            rows.append((label, clmax, mesher, m.NodeCount, m.VolumeCount, wall, min_deg, below_10,
                         (error or "").strip().splitlines()[-1:] if error else ""))
        FreeCAD.closeDocument(doc.Name)
    print("\n| model | CharacteristicLengthMax | mesher | nodes | tets | create_mesh wall | min dihedral | "
          "tets < 10 deg | note |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print("| {} | {} mm | {} | {} | {} | {:.2f} s | {:.2f} deg | {} | {} |".format(*r))


try:
    main()
except Exception:
    traceback.print_exc()
    sys.exit(1)
