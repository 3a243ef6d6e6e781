# QualMesh FEM mesher for FreeCAD: receive QualMesh's .unv through FreeCAD's own UNV import (Fem.read, SMESH's
# DriverUNV in C++), the other reader beside meshreader.py's .inp one.
#
# Fem.read keeps QualMesh's groups as Solid<r> (Volume), Face<m> (Face), Face<m>_Nodes (Node), Edge<e> (Edge),
# Edge<e>_Nodes (Node). The node groups are renamed Face<m> / Edge<e> (type Node), so that both readers give the
# same groups. Quality figures and the check of the names against the shape need coordinates and tetrahedra as
# arrays, which a Fem.FemMesh gives only one call per element (4.6 s per 1M tets): the node (2411) and element
# (2412) datasets are parsed as well, tetrahedra corners only. Not the default: on 1.05M C3D10 Fem.read alone
# takes 11-17 s, against 16-23 s for the whole .inp path (statistics included), and the element records need a
# Python loop here; it is kept for parity with FreeCAD's native import (it also gives the Edge<e> line elements).

import re

import numpy as np

from . import meshreader

_BEAM_TYPES = {11, 21, 22, 24}  # element types whose record 2 is the beam orientation record
_TET_TYPES = {111: (0, 1, 2, 3), 118: (0, 2, 4, 9)}  # corner positions (118: corners and mid nodes interleaved)
_DATASET_END = re.compile(r"^ +-1$", re.M)


def _datasets(text):
    """{dataset number: its text after the number line} for the datasets 2411 and 2412."""
    result = {}
    for chunk in _DATASET_END.split(text):
        head, _, body = chunk.lstrip("\n").partition("\n")
        if head.strip() in ("2411", "2412"):
            result[int(head)] = body
    return result


def parse_unv_geometry(path):
    """A meshreader.DeckMesh holding the nodes and the tetrahedra's corner nodes (element_nodes (T, 4)); groups
    are left to Fem.read."""
    with open(path, "r") as f:
        data = _datasets(f.read())
    if 2411 not in data or 2412 not in data:
        raise meshreader.DeckError("{}: no node (2411) or element (2412) dataset".format(path))
    lines = data[2411].rstrip("\n").split("\n")
    deck = meshreader.DeckMesh()
    deck.node_ids = np.fromstring(" ".join(lines[0::2]), dtype=np.int64, sep=" ").reshape(-1, 4)[:, 0]
    deck.node_xyz = np.fromstring(" ".join(lines[1::2]).replace("D", "E"), dtype=np.float64,
                                  sep=" ").reshape(-1, 3)
    lines = data[2412].rstrip("\n").split("\n")
    ids, corners = [], []
    i, n = 0, len(lines)
    while i < n:
        head = lines[i].split()
        element_id, fe_type, count = int(head[0]), int(head[1]), int(head[5])
        i += 2 if fe_type in _BEAM_TYPES else 1
        node_lines = (count + 7) // 8
        if fe_type in _TET_TYPES:
            nodes = " ".join(lines[i:i + node_lines]).split()
            ids.append(element_id)
            corners.append([int(nodes[k]) for k in _TET_TYPES[fe_type]])
        i += node_lines
    if not ids:
        raise meshreader.DeckError("{}: no tetrahedra".format(path))
    deck.element_ids = np.array(ids, dtype=np.int64)
    deck.element_nodes = np.array(corners, dtype=np.int64)
    return deck


def read_unv(path):
    """(Fem.FemMesh from Fem.read with its node groups renamed, DeckMesh of the geometry with the groups'
    node sets and solids, for quality figures and name matching)."""
    import Fem
    mesh = Fem.read(path)
    deck = parse_unv_geometry(path)
    for group in list(mesh.Groups):
        name, kind = mesh.getGroupName(group), mesh.getGroupElementType(group)
        if kind == "Node" and name.endswith("_Nodes"):
            ids = mesh.getGroupElements(group)
            new_name = name[:-len("_Nodes")]
            mesh.removeGroup(group)
            mesh.addGroupElements(mesh.addGroup(new_name, "Node"), list(ids))
            deck.node_sets[new_name] = np.array(ids, dtype=np.int64)
        elif kind == "Volume":
            deck.solids[name] = np.array(mesh.getGroupElements(group), dtype=np.int64)
    return mesh, deck


def rename_femmesh_groups(mesh, renaming):
    """Apply {old: new} to every group of a Fem.FemMesh named `old` (any type), at once."""
    moved = []
    for group in list(mesh.Groups):
        name = mesh.getGroupName(group)
        if name in renaming:
            moved.append((renaming[name], mesh.getGroupElementType(group), mesh.getGroupElements(group)))
            mesh.removeGroup(group)
    for name, kind, ids in moved:
        mesh.addGroupElements(mesh.addGroup(name, kind), list(ids))
