# Run by `freecadcmd`: the headless API's failure paths. A long run cancelled through its threading.Event stops
# the process and leaves the mesh object as it was; mesh_shape raises QualMeshCancelled on cancel and
# QualMeshError on a shape without a solid. Writes JSON facts to $QUALMESH_FC_RESULT; exit 1 on any exception.

import json
import os
import sys
import threading
import time
import traceback

RESULT = {"errors": []}


def main():
    import FreeCAD
    import Part
    import qualmesh_fem

    doc = FreeCAD.newDocument("Cancel")
    box = doc.addObject("Part::Box", "Box")
    box.Length, box.Width, box.Height = 100, 10, 10
    doc.recompute()
    obj = qualmesh_fem.make_mesh_qualmesh(doc)
    obj.Part = box
    obj.CharacteristicLengthMax = 5.0
    first = qualmesh_fem.QualMeshTools(obj).create_mesh()
    before = (obj.FemMesh.NodeCount, obj.FemMesh.VolumeCount, obj.Nodes, obj.Tetrahedra,
              obj.MinDihedralAngle.Value, obj.CharacteristicLengthMax.Value)
    RESULT["first"] = {"status": first.status, "nodes": obj.FemMesh.NodeCount}

    # a run of about a minute (about 1.5M tetrahedra at --size 0.3), cancelled after 1.5 s
    obj.CharacteristicLengthMax = 0.3
    expected = before[:5] + (0.3,)
    tools = qualmesh_fem.QualMeshTools(obj)
    cancel = threading.Event()
    threading.Timer(1.5, cancel.set).start()
    t0 = time.time()
    result = tools.create_mesh(cancel_event=cancel)
    RESULT["cancel"] = {"status": result.status, "message": result.message, "wall_s": time.time() - t0,
                        "process_exit": tools.run.process.poll(),
                        "unchanged": (obj.FemMesh.NodeCount, obj.FemMesh.VolumeCount, obj.Nodes, obj.Tetrahedra,
                                      obj.MinDihedralAngle.Value, obj.CharacteristicLengthMax.Value) == expected}

    # a mesh region (FEM's own object): its local size reaches qualmesh, or the run says it could not
    import ObjectsFem
    region = ObjectsFem.makeMeshRegion(doc, obj, 1.0, "Region")
    region.References = [(box, "Face1")]
    obj.CharacteristicLengthMax = 5.0
    regional = qualmesh_fem.QualMeshTools(obj).create_mesh()
    command = [line for line in regional.log if " mesh " in line and "--order" in line]
    RESULT["region"] = {"status": regional.status, "warnings": regional.warnings,
                        "local_size_passed": bool(command) and "--local-size Face1=1.0" in command[0]}

    # the API: mesh_shape, cancelled and refused
    cancel = threading.Event()
    threading.Timer(1.0, cancel.set).start()
    try:
        qualmesh_fem.mesh_shape(Part.makeBox(100, 10, 10), max_size=0.3, cancel_event=cancel)
        RESULT["api_cancel"] = "returned"
    except qualmesh_fem.QualMeshCancelled as e:
        RESULT["api_cancel"] = "cancelled: {}".format(e)
    try:
        qualmesh_fem.mesh_shape(Part.makePlane(10, 10), max_size=2)
        RESULT["api_no_solid"] = "returned"
    except qualmesh_fem.QualMeshError as e:
        RESULT["api_no_solid"] = "refused: {}".format(e)
    # the two readers (QualMesh's .inp with numpy, its .unv through Fem.read) give the same mesh and groups
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from fchelpers import canonical_tets, mesh_groups
    cylinder = Part.makeCylinder(5, 20)
    meshes = {}
    for reader in ("inp", "unv"):
        os.environ["QUALMESH_FEM_READER"] = reader
        meshes[reader] = qualmesh_fem.mesh_shape(cylinder, max_size=4)
    del os.environ["QUALMESH_FEM_READER"]
    node_groups = {r: sorted(g for g in mesh_groups(m) if g[1] in ("Node", "Volume", "Face"))
                   for r, m in meshes.items()}
    RESULT["readers"] = {"same_tets": canonical_tets(meshes["inp"]) == canonical_tets(meshes["unv"]),
                         "same_groups": node_groups["inp"] == node_groups["unv"],
                         "unv_edge_groups": sum(1 for g in mesh_groups(meshes["unv"]) if g[1] == "Edge"),
                         "groups": {r: len(g) for r, g in node_groups.items()}}
    lines = []
    femmesh = qualmesh_fem.mesh_shape(Part.makeBox(10, 10, 10), max_size=4, order=1, log=lines.append)
    RESULT["api_linear"] = {"nodes": femmesh.NodeCount, "volumes": femmesh.VolumeCount,
                            "nodes_per_tet": len(femmesh.getElementNodes(femmesh.Volumes[0])),
                            "log_lines": len(lines)}


try:
    main()
except Exception:
    RESULT["errors"].append(traceback.format_exc())
    sys.stderr.write(traceback.format_exc())
with open(os.environ["QUALMESH_FC_RESULT"], "w") as f:
    json.dump(RESULT, f, indent=1)
sys.exit(1 if RESULT["errors"] else 0)
