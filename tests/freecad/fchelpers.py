# Helpers shared by the freecadcmd scripts of tests/freecad/ (imported inside FreeCAD; no module-level work).


def mesh_groups(femmesh):
    return sorted((femmesh.getGroupName(g), femmesh.getGroupElementType(g), len(femmesh.getGroupElements(g)))
                  for g in femmesh.Groups)


def tet_facts(femmesh):
    """How many corner tets are negatively (SMESH's convention) and positively oriented."""
    negative = positive = 0
    for v in femmesh.Volumes:
        ids = femmesh.getElementNodes(v)
        p = [femmesh.getNodeById(i) for i in ids[:4]]
        det = (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0])
        if det < 0:
            negative += 1
        else:
            positive += 1
    return {"negative": negative, "positive": positive}


def canonical_tets(femmesh):
    """Each tet as (sorted corners, orientation sign, {edge: mid node}) in SMESH's node order, for comparing two
    readers of the same mesh independently of where each starts its corner cycle."""
    pairs = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
    result = {}
    for v in femmesh.Volumes:
        ids = femmesh.getElementNodes(v)
        p = [femmesh.getNodeById(i) for i in ids[:4]]
        sign = 1 if (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) > 0 else -1
        mids = tuple(sorted((tuple(sorted((ids[a], ids[b]))), ids[4 + k]) for k, (a, b) in enumerate(pairs))) \
            if len(ids) == 10 else ()
        result[v] = (tuple(sorted(ids[:4])), sign, mids)
    return result
