# QualMesh FEM mesher for FreeCAD: read a QualMesh CalculiX deck (.inp) into a Fem.FemMesh.
#
# The deck is what `qualmesh mesh ... -o OUT.inp` writes: C3D4 or C3D10 elements in one *ELEMENT block per solid
# (ELSET=Solid<r>), *NSET Face<m> and Edge<e> (every node of the CAD face or edge, mid nodes included) and
# *SURFACE Face<m>, TYPE=ELEMENT (element faces S1..S4). It becomes a Fem.FemMesh with
#   - the nodes under their deck ids, the tetrahedra under their deck ids, in SMESH's node order;
#   - one triangle (3 or 6 nodes) per boundary element face, outward, ids after the last tetrahedron;
#   - groups as FreeCAD names the CAD entities: Solid<r> (Volume), Face<m> (Face: the triangles of the CAD face),
#     Face<m> (Node), Edge<e> (Node). A Node and a Face group sharing a name is FEM's own convention (Gmsh's
#     GroupsOfNodes); meshtools looks groups up by name and type, and the pair survives saving (FCStd stores UNV).
# Why not Fem.read of QualMesh's .unv, which keeps the groups too (unvreader.py): the quality figures and the name
# check need coordinates and tetrahedra as arrays, which the deck gives here for free; with them, the .unv path
# is the slower one (see qualmeshtools.result_format).
#
# Node orders (checked against Fem.read of the same mesh written as .unv): SMESH's 4-node tet is negatively
# oriented, CalculiX's positively: C3D4 = smesh[1, 0, 2, 3]; the 10-node tet is the corners then the mid nodes
# m01 m12 m02 m03 m13 m23 in SMESH, m01 m12 m20 m03 m13 m23 in CalculiX: C3D10 = smesh[1, 0, 2, 3, 4, 6, 5, 8, 7, 9].
# The permutation is its own inverse, so smesh = ccx[perm] as well.

import re

import numpy as np

# CalculiX local node indices (0-based) of the element faces S1..S4: corners, then mid nodes (a tria6's
# m01 m12 m20). Each face is listed with its normal pointing into the element; it is reversed when written.
_CCX_FACES = (
    (0, 1, 2, 4, 5, 6),
    (0, 3, 1, 7, 8, 4),
    (1, 3, 2, 8, 9, 5),
    (2, 3, 0, 9, 7, 6),
)
_CCX_TO_SMESH = {4: [1, 0, 2, 3], 10: [1, 0, 2, 3, 4, 6, 5, 8, 7, 9]}
_NODES_PER_TYPE = {"C3D4": 4, "C3D10": 10}
_KEYWORD_VALUE = re.compile(r"\s*([A-Za-z]+)\s*=\s*([^,\s]+)")


class DeckError(Exception):
    """The deck is not a QualMesh tetrahedral deck (names the line or the keyword that is wrong)."""


class DeckMesh(object):
    """A parsed deck, as numpy arrays.

    node_ids (N,) int64 and node_xyz (N, 3) float64 in model units (mm in FreeCAD);
    element_ids (T,) int64, element_nodes (T, 4 or 10) int64 node ids in CalculiX order;
    solids {name: element id array}; node_sets {name: node id array}; surfaces {name: (element ids, side 0..3)}.
    """

    def __init__(self):
        self.node_ids = None
        self.node_xyz = None
        self.element_ids = []
        self.element_nodes = []
        self.solids = {}
        self.node_sets = {}
        self.surfaces = {}

    @property
    def nodes_per_element(self):
        return self.element_nodes.shape[1]


def _numbers(body, dtype):
    """All numbers of a data block (commas, spaces and newlines separate them). np.fromstring's text mode parses
    in C: 1.7 s instead of 2.5 s for 1.45M nodes, 0.9 s instead of 2.9 s for 1.05M C3D10 elements."""
    return np.fromstring(body.replace(",", " "), dtype=dtype, sep=" ")


def _options(header):
    return {k.upper(): v for k, v in _KEYWORD_VALUE.findall(header)}


def parse_deck(path):
    """Parse a QualMesh .inp deck into a DeckMesh. Raises DeckError on anything it does not understand."""
    with open(path, "r") as f:
        text = f.read()
    deck = DeckMesh()
    node_blocks = []
    element_types = set()
    # Every keyword line starts with '*' at the beginning of a line; '**' lines are comments.
    for block in ("\n" + text).split("\n*")[1:]:
        header, _, body = block.partition("\n")
        if header.startswith("*"):
            continue
        keyword = header.split(",")[0].strip().upper()
        opts = _options(header)
        if keyword == "NODE":
            node_blocks.append(_numbers(body, np.float64).reshape(-1, 4))
        elif keyword == "ELEMENT":
            etype = opts.get("TYPE", "").upper()
            if etype not in _NODES_PER_TYPE:
                raise DeckError("{}: element type '{}' is not a tetrahedron (C3D4, C3D10)".format(path, etype))
            element_types.add(etype)
            per = _NODES_PER_TYPE[etype] + 1
            values = _numbers(body, np.int64)
            if values.size % per:
                raise DeckError("{}: *ELEMENT, TYPE={} block has {} numbers, not a multiple of {}".format(
                    path, etype, values.size, per))
            table = values.reshape(-1, per)
            deck.element_ids.append(table[:, 0])
            deck.element_nodes.append(table[:, 1:])
            if "ELSET" in opts:
                name = opts["ELSET"]
                previous = deck.solids.get(name)
                deck.solids[name] = table[:, 0] if previous is None else np.concatenate([previous, table[:, 0]])
        elif keyword == "NSET":
            name = opts.get("NSET")
            values = _numbers(body, np.int64)
            if "GENERATE" in header.upper():
                first, last, step = values.reshape(-1, 3).T
                values = np.concatenate([np.arange(a, b + 1, s) for a, b, s in zip(first, last, step)])
            if name not in ("NALL",):
                deck.node_sets[name] = values
        elif keyword == "SURFACE":
            name = opts.get("NAME")
            rows = [line.split(",") for line in body.splitlines() if line.strip()]
            try:
                elements = np.array([int(r[0]) for r in rows], dtype=np.int64)
                sides = np.array([int(r[1].strip().upper().lstrip("S")) - 1 for r in rows], dtype=np.int64)
            except (ValueError, IndexError):
                raise DeckError("{}: *SURFACE {} has a line that is not 'element, S<k>'".format(path, name))
            deck.surfaces[name] = (elements, sides)
    if not node_blocks or not deck.element_ids:
        raise DeckError("{}: no *NODE or no *ELEMENT block".format(path))
    if len(element_types) != 1:
        raise DeckError("{}: mixed element types {}".format(path, sorted(element_types)))
    nodes = np.concatenate(node_blocks)
    deck.node_ids = nodes[:, 0].astype(np.int64)
    deck.node_xyz = nodes[:, 1:]
    deck.element_ids = np.concatenate(deck.element_ids)
    deck.element_nodes = np.concatenate(deck.element_nodes)
    return deck


def _node_index(deck):
    """Array mapping a node id to its row in deck.node_xyz (-1 for an unused id)."""
    index = np.full(int(deck.node_ids.max()) + 1, -1, dtype=np.int64)
    index[deck.node_ids] = np.arange(deck.node_ids.size)
    return index


def boundary_faces(deck):
    """The element faces of every *SURFACE, outward: {name: (T_f, 3 or 6) node id array}.

    A face listed twice in one surface (an interface face listed from both of its solids) is kept once.
    """
    element_row = np.full(int(deck.element_ids.max()) + 1, -1, dtype=np.int64)
    element_row[deck.element_ids] = np.arange(deck.element_ids.size)
    local = np.array(_CCX_FACES)
    if deck.nodes_per_element == 4:
        local = local[:, :3]
    # Written reversed (corners 0 2 1, mid nodes m02 m21 m10) so that the normal points out of the element.
    reverse = [0, 2, 1, 5, 4, 3] if local.shape[1] == 6 else [0, 2, 1]
    result = {}
    for name, (elements, sides) in deck.surfaces.items():
        rows = element_row[elements]
        if (rows < 0).any():
            raise DeckError("*SURFACE {} names element {} that the deck does not define".format(
                name, int(elements[rows < 0][0])))
        faces = deck.element_nodes[rows[:, None], local[sides]][:, reverse]
        _, first = np.unique(np.sort(faces[:, :3], axis=1), axis=0, return_index=True)
        result[name] = faces[np.sort(first)]
    return result


def dihedral_angles_deg(xyz):
    """The six dihedral angles (degrees) of each tetrahedron, xyz (T, 4, 3) corner coordinates -> (T, 6)."""
    p0, p1, p2, p3 = xyz[:, 0], xyz[:, 1], xyz[:, 2], xyz[:, 3]
    # Area vectors of the faces opposite each corner, all oriented the same way relative to the tet.
    n0 = np.cross(p2 - p1, p3 - p1)
    n1 = np.cross(p3 - p0, p2 - p0)
    n2 = np.cross(p1 - p0, p3 - p0)
    n3 = np.cross(p2 - p0, p1 - p0)
    normals = np.stack([n0, n1, n2, n3], axis=1)
    length = np.linalg.norm(normals, axis=2)
    length[length == 0.0] = 1.0
    unit = normals / length[:, :, None]
    pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
    cosines = np.stack([-(unit[:, a] * unit[:, b]).sum(axis=1) for a, b in pairs], axis=1)
    return np.degrees(np.arccos(np.clip(cosines, -1.0, 1.0)))


def quality_figures(deck, chunk=200000):
    """Minimum dihedral angle (deg) and the number of tetrahedra whose smallest dihedral angle is below 10 and
    5 degrees, measured on the corner nodes (the straight-sided tetrahedra), as `qualmesh check` measures them."""
    index = _node_index(deck)
    corners = index[deck.element_nodes[:, :4]]
    min_deg = 180.0
    below_10 = below_5 = 0
    for start in range(0, corners.shape[0], chunk):
        angles = dihedral_angles_deg(deck.node_xyz[corners[start:start + chunk]]).min(axis=1)
        min_deg = min(min_deg, float(angles.min()))
        below_10 += int((angles < 10.0).sum())
        below_5 += int((angles < 5.0).sum())
    return {"min_dihedral_deg": min_deg, "num_tets_below_10_deg": below_10, "num_tets_below_5_deg": below_5}


def build_femmesh(deck, with_faces=True):
    """A new Fem.FemMesh holding the deck's nodes, tetrahedra, boundary triangles and groups (see the file header).

    Needs FreeCAD's Fem module; mutates nothing but the mesh it returns.
    """
    import Fem
    mesh = Fem.FemMesh()
    # map() calls the bound methods without a Python-level loop body (about a third faster on 1M elements).
    _consume(map(mesh.addNode, deck.node_xyz[:, 0].tolist(), deck.node_xyz[:, 1].tolist(),
                 deck.node_xyz[:, 2].tolist(), deck.node_ids.tolist()))
    smesh_order = deck.element_nodes[:, _CCX_TO_SMESH[deck.nodes_per_element]]
    _consume(map(mesh.addVolume, smesh_order.tolist(), deck.element_ids.tolist()))
    for name in sorted(deck.solids, key=_natural_key):
        group = mesh.addGroup(name, "Volume")
        mesh.addGroupElements(group, deck.solids[name].tolist())
    if with_faces and deck.surfaces:
        next_id = int(deck.element_ids.max()) + 1
        add_face = mesh.addFace
        for name, faces in sorted(boundary_faces(deck).items(), key=lambda item: _natural_key(item[0])):
            ids = list(range(next_id, next_id + faces.shape[0]))
            next_id += faces.shape[0]
            _consume(map(add_face, faces.tolist(), ids))
            group = mesh.addGroup(name, "Face")
            mesh.addGroupElements(group, ids)
    for name in sorted(deck.node_sets, key=_natural_key):
        if name in ("EALL",):
            continue
        group = mesh.addGroup(name, "Node")
        mesh.addGroupElements(group, deck.node_sets[name].tolist())
    return mesh


def _consume(iterator):
    for _ in iterator:
        pass


def _natural_key(name):
    """Face2 before Face10."""
    return [int(part) if part.isdigit() else part for part in re.split(r"(\d+)", name)]
