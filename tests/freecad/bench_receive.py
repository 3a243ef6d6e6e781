# Run by `freecadcmd` (a measurement, not a test): how long FreeCAD takes to receive a QualMesh mesh, that is the
# tool's overhead beyond meshing: parse the deck, match the group names, build the Fem.FemMesh, measure quality,
# assign obj.FemMesh; and, for comparison, Fem.read of the same mesh as .unv plus its assignment.
#   QUALMESH_BENCH_INP=big.inp [QUALMESH_BENCH_UNV=big.unv] [QUALMESH_BENCH_BOX=100,10,10] freecadcmd bench_receive.py
import os
import sys
import time
import traceback


def main():
    import FreeCAD
    import Fem
    import Part
    from qualmesh_fem import entitymatch, meshreader

    box = [float(v) for v in os.environ.get("QUALMESH_BENCH_BOX", "100,10,10").split(",")]
    shape = Part.makeBox(*box)
    doc = FreeCAD.newDocument("Bench")
    obj = doc.addObject("Fem::FemMeshObjectPython", "Mesh")
    times = {}
    t = time.time()
    deck = meshreader.parse_deck(os.environ["QUALMESH_BENCH_INP"])
    times["parse"] = time.time() - t
    t = time.time()
    renaming, _ = entitymatch.freecad_names(deck, shape)
    times["match_names"] = time.time() - t
    t = time.time()
    mesh = meshreader.build_femmesh(deck)
    times["build_femmesh"] = time.time() - t
    t = time.time()
    quality = meshreader.quality_figures(deck)
    times["quality"] = time.time() - t
    t = time.time()
    obj.FemMesh = mesh
    times["assign"] = time.time() - t
    total = sum(times.values())
    print("\nRECEIVE inp: {} nodes, {} tets, {} faces, {} groups; ".format(
        mesh.NodeCount, mesh.VolumeCount, mesh.FaceCount, mesh.GroupCount) +
        ", ".join("{} {:.2f} s".format(k, v) for k, v in times.items()) + "; total {:.2f} s".format(total))
    print("\nRECEIVE quality: {}".format(quality))
    unv = os.environ.get("QUALMESH_BENCH_UNV")
    if unv:
        del mesh
        obj2 = doc.addObject("Fem::FemMeshObjectPython", "Mesh2")
        t = time.time()
        other = Fem.read(unv)
        read_s = time.time() - t
        t = time.time()
        obj2.FemMesh = other
        assign_s = time.time() - t
        print("\nRECEIVE unv: Fem.read {:.2f} s, assign {:.2f} s, total {:.2f} s ({} nodes, {} tets)".format(
            read_s, assign_s, read_s + assign_s, other.NodeCount, other.VolumeCount))


try:
    main()
except Exception:
    traceback.print_exc()
    sys.exit(1)
