# QualMesh FEM mesher for FreeCAD: make the mesh's group names FreeCAD's names of the same CAD entities.
#
# QualMesh numbers the faces, edges and solids of the shape it healed (TopExp::MapShapes order), which is FreeCAD's
# Face<i>/Edge<i>/Solid<i> naming of the shape it exported, unless healing reordered them: measured on a
# Part::Cylinder, QualMesh's Edge2 and Edge3 are FreeCAD's Edge3 and Edge2. So every group is checked against
# the entity FreeCAD gives its name to, on five of its nodes, a majority of which must lie on it (nodes of one face
# only, or of one edge only: they tell neighbouring entities apart); a group whose nodes lie on another entity is
# renamed after that one. A renaming is applied only when it is one-to-one; otherwise the names are kept and a
# warning says so.
# Cost: five point-to-shape distances per group when the names agree (about 0.1 s on part.step's 96 groups).

import numpy as np

_SAMPLES = 5


def _samples(ids, exclude, count=_SAMPLES):
    """Up to `count` ids spread over `ids`, preferring those not in `exclude`."""
    own = ids[~np.isin(ids, exclude)] if exclude.size else ids
    pool = own if own.size >= count else ids
    if pool.size == 0:
        return pool
    return pool[np.linspace(0, pool.size - 1, min(count, pool.size)).astype(int)]


def _on(entity, points, tol):
    import Part
    return sum(1 for p in points if entity.distToShape(Part.Vertex(*p))[0] <= tol)


def _match(kind, names, entities, points_of, test, warnings):
    """{old name: new name} for groups `names` of one kind ('Face', 'Edge', 'Solid')."""
    renaming = {}
    for name in names:
        index = int(name[len(kind):]) - 1
        points = points_of(name)
        if len(points) == 0:
            continue
        need = (len(points) + 1) // 2
        if 0 <= index < len(entities) and test(entities[index], points) >= need:
            continue
        hits = [(test(entity, points), j) for j, entity in enumerate(entities)]
        best, j = max(hits)
        if best >= need:
            renaming[name] = "{}{}".format(kind, j + 1)
        else:
            warnings.append("{}: no {} of the shape holds its nodes; name kept".format(name, kind.lower()))
    if renaming:
        final = {name: renaming.get(name, name) for name in names}
        if len(set(final.values())) != len(final):
            warnings.append("{} groups could not be matched one-to-one with the shape's {}s ({}); names kept"
                            .format(kind, kind.lower(), renaming))
            return {}
    return renaming


def freecad_names(deck, shape):
    """({deck group name: FreeCAD name} for the groups to rename, warnings). Mutates nothing."""
    index = np.full(int(deck.node_ids.max()) + 1, -1, dtype=np.int64)
    index[deck.node_ids] = np.arange(deck.node_ids.size)
    diag = shape.BoundBox.DiagonalLength
    warnings = []

    face_names = sorted(n for n in deck.node_sets if n.startswith("Face") and n[4:].isdigit())
    edge_names = sorted(n for n in deck.node_sets if n.startswith("Edge") and n[4:].isdigit())
    edge_nodes = np.concatenate([deck.node_sets[n] for n in edge_names]) if edge_names else np.zeros(0, np.int64)
    unique, counts = np.unique(edge_nodes, return_counts=True)
    vertex_nodes = unique[counts > 1]

    def node_points(exclude):
        def points_of(name):
            return deck.node_xyz[index[_samples(deck.node_sets[name], exclude)]].tolist()
        return points_of

    def surface_test(entity, points):
        return _on(entity, points, max(entity.Tolerance, 1e-9 * diag) + 1e-7 * diag)

    renaming = {}
    renaming.update(_match("Face", face_names, shape.Faces, node_points(edge_nodes), surface_test, warnings))
    renaming.update(_match("Edge", edge_names, shape.Edges, node_points(vertex_nodes), surface_test, warnings))

    element_row = np.full(int(deck.element_ids.max()) + 1, -1, dtype=np.int64)
    element_row[deck.element_ids] = np.arange(deck.element_ids.size)

    def centroids(name):
        ids = _samples(deck.solids[name], np.zeros(0, np.int64))
        corners = deck.element_nodes[element_row[ids]][:, :4]
        return deck.node_xyz[index[corners]].mean(axis=1).tolist()

    def inside_test(solid, points):
        import FreeCAD
        return sum(1 for p in points if solid.isInside(FreeCAD.Vector(*p), 1e-7 * diag, True))

    solid_names = sorted(n for n in deck.solids if n.startswith("Solid") and n[5:].isdigit())
    renaming.update(_match("Solid", solid_names, shape.Solids, centroids, inside_test, warnings))
    return renaming, warnings


def rename_groups(deck, renaming):
    """Apply {old: new} to the deck's node sets, surfaces and solids at once (a swap stays a swap)."""
    for table in (deck.node_sets, deck.surfaces, deck.solids):
        moved = {renaming[name]: table.pop(name) for name in list(table) if name in renaming}
        table.update(moved)
