#!/usr/bin/env python3
"""Generate the gather scenarios in maps/: office, warehouse, campus, cave.

For each scenario NAME this writes, next to this script (or into --outdir):
  NAME.png           8-bit grayscale, 254 free, 0 occupied, 205 unknown (row 0 = top)
  NAME.yaml          ROS map_server metadata (trinary mode)
  NAME.scenario.yaml gather scenario (DESIGN.md "Scenario file"), every section written out

Everything is deterministic (fixed seeds, no clock): running the script twice
gives byte-identical files. Needs only numpy and PIL (Debian python3-numpy,
python3-pil); if the python3 found first on PATH lacks them the script re-runs
itself with /usr/bin/python3.

usage: python3 maps/generate.py [--outdir DIR] [NAME ...]
"""
import os
import sys

try:
    import numpy as np
    from PIL import Image
except ImportError:
    _sys_py = "/usr/bin/python3"
    if os.path.exists(_sys_py) and os.path.realpath(sys.executable) != os.path.realpath(_sys_py):
        os.execv(_sys_py, [_sys_py] + sys.argv)
    raise

FREE, OCC, UNK = 254, 0, 205


class MapError(Exception):
    pass


# ---------------------------------------------------------------------------
# raster helpers
# ---------------------------------------------------------------------------

def box_count(mask, k):
    """Number of True cells in the (2k+1) x (2k+1) window centred on each cell
    (cells outside the image count as False)."""
    m = np.pad(mask.astype(np.int32), k)
    c = np.zeros((m.shape[0] + 1, m.shape[1]), np.int32)
    np.cumsum(m, axis=0, out=c[1:])
    m = c[2 * k + 1:] - c[:-2 * k - 1]
    c = np.zeros((m.shape[0], m.shape[1] + 1), np.int32)
    np.cumsum(m, axis=1, out=c[:, 1:])
    return c[:, 2 * k + 1:] - c[:, :-2 * k - 1]


def erode(mask, k):
    return box_count(mask, k) == (2 * k + 1) ** 2


def dilate(mask, k):
    return box_count(mask, k) > 0


def disk_dilate(mask, rad):
    """Dilate by a disk of radius rad (cells): union over rows dy of a horizontal
    dilation by the disk's half-width at dy, shifted by dy."""
    H, W = mask.shape
    k = int(rad)
    m = mask.astype(np.int32)
    c = np.zeros((H, W + 2 * k + 1), np.int32)
    np.cumsum(np.pad(m, ((0, 0), (k, k))), axis=1, out=c[:, 1:])
    out = np.zeros((H, W), bool)
    for dy in range(-k, k + 1):
        hw = int(np.sqrt(max(0.0, rad * rad - dy * dy)))
        rowdil = (c[:, k + hw + 1:k + hw + 1 + W] - c[:, k - hw:k - hw + W]) > 0
        if dy >= 0:
            out[dy:, :] |= rowdil[:H - dy, :]
        else:
            out[:dy, :] |= rowdil[-dy:, :]
    return out


def disk_erode(mask, rad):
    return ~disk_dilate(~mask, rad)


def box_blur(f, k):
    """Mean over a (2k+1)^2 window, edge values replicated."""
    p = np.pad(f.astype(np.float64), k, mode="edge")
    c = np.zeros((p.shape[0] + 1, p.shape[1]))
    np.cumsum(p, axis=0, out=c[1:])
    p = c[2 * k + 1:] - c[:-2 * k - 1]
    c = np.zeros((p.shape[0], p.shape[1] + 1))
    np.cumsum(p, axis=1, out=c[:, 1:])
    return (c[:, 2 * k + 1:] - c[:, :-2 * k - 1]) / float((2 * k + 1) ** 2)


def label4(mask):
    """4-connected component labelling by row runs + union-find.
    Returns (labels int32 image with 0 = background, sizes array indexed by label)."""
    H, W = mask.shape
    m = np.zeros((H, W + 2), np.int8)
    m[:, 1:-1] = mask
    d = np.diff(m, axis=1)
    sr, sc = np.nonzero(d == 1)
    er, ec = np.nonzero(d == -1)
    assert np.array_equal(sr, er)
    n = len(sr)
    parent = list(range(n))

    def find(x):
        root = x
        while parent[root] != root:
            root = parent[root]
        while parent[x] != root:
            parent[x], x = root, parent[x]
        return root

    row_start = np.searchsorted(sr, np.arange(H + 1)).tolist()
    s, e = sc.tolist(), ec.tolist()
    for r in range(H - 1):
        i, iend = row_start[r], row_start[r + 1]
        j, jend = iend, row_start[r + 2]
        while i < iend and j < jend:
            if s[i] < e[j] and s[j] < e[i]:
                a, b = find(i), find(j)
                if a != b:
                    parent[max(a, b)] = min(a, b)
            if e[i] < e[j]:
                i += 1
            else:
                j += 1
    roots = [find(i) for i in range(n)]
    ids = {}
    lab = np.zeros((H, W), np.int32)
    sizes = [0]
    rows = sr.tolist()
    for i in range(n):
        rt = roots[i]
        if rt not in ids:
            ids[rt] = len(sizes)
            sizes.append(0)
        k = ids[rt]
        lab[rows[i], s[i]:e[i]] = k
        sizes[k] += e[i] - s[i]
    return lab, np.array(sizes, np.int64)


def disk(a, r, c, rad, value):
    """Set a filled disk (centre r, c in cells, float ok) to value."""
    H, W = a.shape
    r0, r1 = max(0, int(r - rad) - 1), min(H, int(r + rad) + 2)
    c0, c1 = max(0, int(c - rad) - 1), min(W, int(c + rad) + 2)
    if r0 >= r1 or c0 >= c1:
        return
    yy, xx = np.mgrid[r0:r1, c0:c1]
    a[r0:r1, c0:c1][(yy - r) ** 2 + (xx - c) ** 2 <= rad * rad] = value


class Walls:
    """Axis-aligned wall drawing with checked door openings."""

    def __init__(self, a):
        self.a = a

    def h(self, r, c0, c1, t):
        """Horizontal wall: rows [r, r+t), cols [c0, c1)."""
        self.a[r:r + t, c0:c1] = OCC

    def v(self, c, r0, r1, t):
        """Vertical wall: cols [c, c+t), rows [r0, r1)."""
        self.a[r0:r1, c:c + t] = OCC

    def hdoor(self, r, c, w, t):
        """Opening of width w (cols [c, c+w)) through the horizontal wall at rows [r, r+t)."""
        a = self.a
        if not (a[r:r + t, c:c + w] == OCC).all():
            raise MapError("hdoor r=%d c=%d w=%d: not entirely wall" % (r, c, w))
        if not ((a[r - 1, c:c + w] == FREE).all() and (a[r + t, c:c + w] == FREE).all()):
            raise MapError("hdoor r=%d c=%d w=%d: does not open free space on both sides" % (r, c, w))
        a[r:r + t, c:c + w] = FREE

    def vdoor(self, c, r, w, t):
        """Opening of width w (rows [r, r+w)) through the vertical wall at cols [c, c+t)."""
        a = self.a
        if not (a[r:r + w, c:c + t] == OCC).all():
            raise MapError("vdoor c=%d r=%d w=%d: not entirely wall" % (c, r, w))
        if not ((a[r:r + w, c - 1] == FREE).all() and (a[r:r + w, c + t] == FREE).all()):
            raise MapError("vdoor c=%d r=%d w=%d: does not open free space on both sides" % (c, r, w))
        a[r:r + w, c:c + t] = FREE


def place_door(a, orient, fixed, t, e0, e1, w, target, margin, rng=None):
    """Carve a door of width w in the wall at fixed..fixed+t (rows if orient == 'h',
    cols if 'v') somewhere in [e0, e1) along the wall, as near to `target` as
    possible, where both sides are free over the door width plus `margin` (so the
    door does not land on a T-junction with another wall). Returns the start."""
    best = None
    for d in range(e0 + margin, e1 - margin - w + 1):
        if orient == "h":
            wall = a[fixed:fixed + t, d:d + w]
            s1 = a[fixed - 1, d - margin:d + w + margin]
            s2 = a[fixed + t, d - margin:d + w + margin]
        else:
            wall = a[d:d + w, fixed:fixed + t]
            s1 = a[d - margin:d + w + margin, fixed - 1]
            s2 = a[d - margin:d + w + margin, fixed + t]
        if (wall == OCC).all() and (s1 == FREE).all() and (s2 == FREE).all():
            if best is None or abs(d - target) < abs(best - target):
                best = d
    if best is None:
        raise MapError("no room for a %d-cell door in %s-wall at %d, [%d, %d)" % (w, orient, fixed, e0, e1))
    if orient == "h":
        a[fixed:fixed + t, best:best + w] = FREE
    else:
        a[best:best + w, fixed:fixed + t] = FREE
    return best


# ---------------------------------------------------------------------------
# scenario 1: office floor (default)
# ---------------------------------------------------------------------------

def make_office():
    H, W, res = 700, 1200, 0.05
    a = np.full((H, W), UNK, np.uint8)
    a[10:690, 10:1190] = OCC          # exterior wall 0.2 m, unknown outside the building
    a[14:686, 14:1186] = FREE
    t = 4                              # interior walls 0.2 m
    w = Walls(a)
    # Horizontal bands (rows):   A rooms 14-180 | B north corridor 184-216 |
    # C rooms 220-320 | D main corridor 324-364 (2 m) | E rooms 368-530 |
    # F south corridor 534-566 | G rooms 570-686.  West lobby cols 14-200, rows 184-566.
    w.h(180, 14, 1186, t)
    w.h(216, 200, 1186, t)
    w.h(320, 200, 1186, t)
    w.h(364, 200, 1186, t)
    w.h(530, 200, 1186, t)
    w.h(566, 14, 1186, t)
    w.v(200, 216, 324, t)              # lobby east wall beside band C
    w.v(200, 364, 534, t)              # lobby east wall beside band E
    for c in (200, 330, 460, 580, 700, 1000, 1100):           # band A
        w.v(c, 14, 180, t)
    for c in (330, 460, 596, 632, 760, 890, 1030):            # band C (596-636: side corridor V1)
        w.v(c, 220, 320, t)
    for c in (340, 480, 620, 760, 856, 892):                  # band E (856-896: side corridor V2)
        w.v(c, 368, 530, t)
    w.h(450, 344, 480, t)              # E2 split into two rooms
    for c in (200, 320, 440, 560, 680, 820):                  # band G
        w.v(c, 570, 686, t)
    # furniture-like solid blocks
    a[470:566, 14:84] = OCC            # lift / stair core in the lobby (solid)
    a[250:262, 70:150] = OCC           # reception counter
    for c in (900, 980, 1060, 1140):   # pillars in hall G6
        a[624:632, c:c + 8] = OCC
    for r in (400, 466):               # desk islands in open-plan office E6
        for c in (940, 1060):
            a[r:r + 32, c:c + 64] = OCC
    # side corridors V1 (band C) and V2 (band E): full-width openings
    w.hdoor(216, 600, 32, t)
    w.hdoor(320, 600, 32, t)
    w.hdoor(364, 860, 32, t)
    w.hdoor(530, 860, 32, t)
    # doors: (wall row, door start col, width)
    hdoors = [
        # band A -> lobby / north corridor (wall at row 180)
        (180, 150, 24), (180, 216, 20), (180, 428, 20), (180, 476, 20), (180, 660, 20),
        (180, 730, 24), (180, 950, 24), (180, 1016, 20), (180, 1150, 20),
        # band C: to north corridor (row 216) or main corridor (row 320)
        (216, 220, 20), (320, 420, 20), (216, 530, 20), (320, 560, 20), (216, 700, 20),
        (320, 780, 20), (216, 960, 20), (320, 1050, 22), (216, 1150, 20),
        # band E: to main corridor (row 364) or south corridor (row 530)
        (364, 300, 22), (364, 360, 20), (530, 450, 20), (364, 580, 20), (530, 700, 20),
        (364, 780, 20), (364, 910, 24), (364, 1140, 24), (530, 1010, 24),
        # band G -> south corridor / lobby (wall at row 566)
        (566, 120, 24), (566, 220, 20), (566, 400, 20), (566, 460, 20), (566, 640, 20),
        (566, 700, 20), (566, 850, 24), (566, 1120, 24),
    ]
    for r, c, dw in hdoors:
        w.hdoor(r, c, dw, t)
    # internal doors between neighbouring rooms: (wall col, door start row, width)
    for c, r, dw in [(330, 40, 20), (1100, 60, 20), (320, 620, 20)]:
        w.vdoor(c, r, dw, t)
    oc_cell = (344, 110)               # lobby, at the mouth of the main corridor
    comment = ("office floor, 29 rooms and halls (doors 0.9-1.2 m, walls 0.2 m) off a 2 m main corridor, "
               "north and south 1.6 m corridors, two side corridors and a west lobby")
    return dict(a=a, res=res, origin=(0.0, 0.0), oc_cell=oc_cell, comment=comment,
                oc_note="west lobby at the mouth of the main corridor")


# ---------------------------------------------------------------------------
# scenario 2: warehouse
# ---------------------------------------------------------------------------

def make_warehouse():
    H, W, res = 800, 1000, 0.05
    a = np.full((H, W), UNK, np.uint8)
    a[10:790, 10:990] = OCC           # exterior wall 0.3 m
    a[16:784, 16:984] = FREE
    w = Walls(a)
    # loading / office area (cols 16-260) | dividing wall 260-266 | storage (266-984)
    w.v(260, 16, 784, 6)
    for r in (300, 480, 660):          # 3 m wide openings (roller doors)
        w.vdoor(260, r, 60, 6)
    # office block in the loading area: two offices
    w.h(250, 16, 260, 4)
    w.v(130, 16, 250, 4)
    w.hdoor(250, 50, 20, 4)
    w.hdoor(250, 200, 20, 4)
    a[60:90, 160:230] = OCC            # desks
    a[60:90, 40:100] = OCC
    # pallet stacks in the loading area (2 m x 2 m), clear of the doors
    for r in (300, 420, 620, 720):
        a[r:r + 40, 16:56] = OCC
    a[700:740, 140:180] = OCC
    # cold room in the north-east corner, forklift door
    w.h(156, 816, 984, 4)
    w.v(816, 16, 160, 4)
    w.hdoor(156, 880, 32, 4)
    # shelving: 10 rows of double racks (1.2 m deep), aisles 2.4 m; front aisle
    # cols 266-330 (3.2 m), back aisle 930-984, cross aisle cols 600-650 for all
    # rows and cols 780-830 for every second row
    for k in range(10):
        r = 64 + 72 * k
        c_end = 770 if k < 2 else 930   # north rows stop before the cold room
        a[r:r + 24, 330:c_end] = OCC
        a[r:r + 24, 600:650] = FREE
        if k % 2 == 1:
            a[r:r + 24, 780:830] = FREE
    # building columns in the front aisle wall line (0.5 m)
    for r in (120, 264, 408, 552, 696):
        a[r:r + 10, 290:300] = OCC
    oc_cell = (500, 190)
    comment = "warehouse with 10 rows of shelving, cross aisles, a cold room and a west loading/office area"
    return dict(a=a, res=res, origin=(0.0, 0.0), oc_cell=oc_cell, comment=comment,
                oc_note="loading area, west side")


# ---------------------------------------------------------------------------
# scenario 3: campus
# ---------------------------------------------------------------------------

class Building:
    def __init__(self, name, rects, ext_doors, max_room, min_room):
        self.name = name
        self.rects = rects              # list of (r0, c0, r1, c1), neighbours overlap by the wall thickness
        self.ext_doors = ext_doors      # list of (rect index, side 'N'/'S'/'W'/'E', fraction, width)
        self.max_room = max_room        # split rooms larger than this (cells)
        self.min_room = min_room


def make_campus():
    H, W, res = 2000, 2200, 0.1
    TE, TI = 3, 2                       # exterior 0.3 m, interior 0.2 m walls
    rng = np.random.default_rng(20240603)
    a = np.full((H, W), FREE, np.uint8)
    # rects: (r0, c0, r1, c1[, kind]); parts of one building overlap by the wall
    # thickness TE. kind "corridor": never split, and every room along a wall it
    # shares with another part gets its own door; an int: max room size there.
    buildings = [
        Building("library", [(150, 150, 290, 650), (287, 150, 320, 650, "corridor"), (317, 150, 450, 650)],
                 [(1, "W", 0.5, 20), (1, "E", 0.5, 20), (2, "S", 0.3, 20)], 130, 60),
        Building("L-block", [(150, 1300, 400, 1900), (397, 1600, 750, 1900)],
                 [(0, "W", 0.5, 20), (1, "S", 0.5, 20), (0, "S", 0.2, 14)], 160, 55),
        Building("U-block", [(1200, 150, 1800, 350), (1600, 347, 1800, 653), (1200, 650, 1800, 850)],
                 [(0, "N", 0.5, 20), (2, "N", 0.5, 20), (1, "N", 0.5, 16)], 150, 55),
        Building("cafe", [(1150, 1150, 1330, 1330)],
                 [(0, "W", 0.5, 20), (0, "N", 0.6, 16)], 120, 60),
        Building("labs", [(1750, 1000, 1785, 1900, "corridor"), (1782, 1000, 1900, 1900)],
                 [(0, "W", 0.5, 20), (0, "E", 0.5, 20), (0, "N", 0.5, 16)], 150, 55),
        Building("sports hall", [(950, 1750, 1240, 2050, "corridor"), (1237, 1750, 1330, 2050, 110)],
                 [(0, "W", 0.3, 20), (0, "N", 0.5, 16)], 400, 60),
        Building("cloister", [(700, 200, 820, 650), (1030, 200, 1150, 650),
                              (817, 200, 1033, 320), (817, 530, 1033, 650)],
                 [(0, "N", 0.5, 20), (1, "S", 0.5, 16), (0, "S", 0.5, 16), (1, "N", 0.5, 16),
                  (3, "E", 0.5, 16)], 140, 50),
        Building("admin", [(450, 850, 700, 1200), (697, 950, 820, 1100)],
                 [(0, "N", 0.5, 20), (1, "S", 0.5, 16), (0, "E", 0.7, 14)], 140, 55),
    ]
    footprint = np.zeros((H, W), bool)
    for b in buildings:
        for rect in b.rects:
            r0, c0, r1, c1 = rect[:4]
            footprint[r0:r1, c0:c1] = True
    # every building: exterior walls of each part, interior BSP rooms (walls first, doors after)
    interior_walls = []                 # (orient, fixed, e0, e1)
    for b in buildings:
        for rect in b.rects:
            r0, c0, r1, c1 = rect[:4]
            a[r0:r1, c0:c1] = OCC
            a[r0 + TE:r1 - TE, c0 + TE:c1 - TE] = FREE
        for rect in b.rects:
            r0, c0, r1, c1 = rect[:4]
            kind = rect[4] if len(rect) > 4 else None
            if kind == "corridor":
                continue
            max_room = kind if isinstance(kind, int) else b.max_room
            bsp(rng, r0 + TE, c0 + TE, r1 - TE, c1 - TE, max_room, b.min_room, TI, a, interior_walls)
    # (the cloister's courtyard is in no rect: it stays open ground)
    # doors in BSP walls (each wall splits a region in two, so one door per wall keeps it connected)
    for (orient, fixed, e0, e1) in interior_walls:
        dw = int(rng.integers(10, 15))
        target = int(rng.integers(e0, e1))
        place_door(a, orient, fixed, TI, e0, e1, dw, target, 3)
    for b in buildings:
        # doors in walls shared by two parts of one building
        for i, p in enumerate(b.rects):
            for q in b.rects[i + 1:]:
                for (x, y) in ((p, q), (q, p)):
                    corridor = "corridor" in (x[4:] + y[4:])
                    other = y if x[4:] == ("corridor",) else x      # the part with rooms
                    if x[2] - TE == y[0]:            # x above y: wall rows [y0, y0+TE)
                        e0, e1 = max(x[1], y[1]) + TE, min(x[3], y[3]) - TE
                        side_row = y[0] + TE if other is y else y[0] - 1
                        shared_doors(a, rng, "h", y[0], TE, e0, e1, corridor, a[side_row, :])
                    if x[3] - TE == y[1]:            # x left of y: wall cols [y1, y1+TE)
                        e0, e1 = max(x[0], y[0]) + TE, min(x[2], y[2]) - TE
                        side_col = y[1] + TE if other is y else y[1] - 1
                        shared_doors(a, rng, "v", y[1], TE, e0, e1, corridor, a[:, side_col])
        for (i, side, frac, dw) in b.ext_doors:
            r0, c0, r1, c1 = b.rects[i][:4]
            if side in "NS":
                fixed = r0 if side == "N" else r1 - TE
                place_door(a, "h", fixed, TE, c0 + TE, c1 - TE, dw, int(c0 + frac * (c1 - c0)), 3)
            else:
                fixed = c0 if side == "W" else c1 - TE
                place_door(a, "v", fixed, TE, r0 + TE, r1 - TE, dw, int(r0 + frac * (r1 - r0)), 3)
    # outdoor obstacles, kept >= 5 m from buildings so no entrance is blocked
    keep_clear = dilate(footprint, 50)
    oc_cell = (999, 1100)              # central open plaza
    keep_clear[oc_cell[0] - 120:oc_cell[0] + 120, oc_cell[1] - 120:oc_cell[1] + 120] = True
    keep_clear[:20, :] = keep_clear[-20:, :] = True
    keep_clear[:, :20] = keep_clear[:, -20:] = True
    # pond with an irregular shore
    pond = np.zeros((H, W), bool)
    pr, pc = 1460, 1560
    yy, xx = np.mgrid[pr - 150:pr + 150, pc - 230:pc + 230]
    th = np.arctan2(yy - pr, xx - pc)
    rr = np.hypot((yy - pr) / 95.0, (xx - pc) / 175.0)
    wob = 1.0 + 0.08 * np.cos(3 * th + 0.7) + 0.05 * np.cos(5 * th + 2.1) + 0.04 * np.sin(7 * th)
    pond[pr - 150:pr + 150, pc - 230:pc + 230] = rr <= wob
    if (pond & keep_clear).any():
        raise MapError("pond too close to a building")
    a[pond] = OCC
    keep_clear |= dilate(pond, 40)
    # parking lot: a row of cars (4.5 m x 2 m) north of the sports hall
    for k in range(13):
        c = 1330 + 30 * k
        a[860:905, c:c + 20] = OCC
    keep_clear[840:925, 1310:1740] = True
    # a couple of low garden walls
    a[1000:1004, 800:920] = OCC
    a[1400:1404, 1000:1100] = OCC
    keep_clear[960:1044, 760:960] = True
    keep_clear[1360:1444, 960:1140] = True
    # clusters of trees / bushes (round trunks and shrubs)
    trees = np.zeros((H, W), np.uint8)
    placed = 0
    tries = 0
    while placed < 22 and tries < 2000:
        tries += 1
        cr, cc = int(rng.integers(60, H - 60)), int(rng.integers(60, W - 60))
        if keep_clear[max(0, cr - 60):cr + 60, max(0, cc - 60):cc + 60].any():
            continue
        n = int(rng.integers(3, 8))
        for _ in range(n):
            rad = float(rng.uniform(4, 12))
            r = cr + float(np.clip(rng.normal(0, 25), -50, 50))
            c = cc + float(np.clip(rng.normal(0, 25), -50, 50))
            disk(trees, r, c, rad, 1)
        keep_clear[cr - 120:cr + 120, cc - 120:cc + 120] = True   # spread the clusters
        placed += 1
    # close gaps under 1 m inside a cluster (shrubs between the trunks): no robot-sized dead pockets
    trees = ~disk_dilate(~disk_dilate(trees.astype(bool), 5), 5)
    a[trees] = OCC
    comment = ("campus of 8 separate buildings with rooms (2-3 entrances each, plus 2 doors into the "
               "cloister's courtyard) in open ground with a pond, tree clusters and a parking lot")
    return dict(a=a, res=res, origin=(-110.0, -100.0), oc_cell=oc_cell, comment=comment,
                oc_note="central open plaza, world (0.05, 0.05)")


def shared_doors(a, rng, orient, fixed, t, e0, e1, corridor, side_line):
    """Doors in the wall two parts of a building share: one in the middle, or, if
    one part is a corridor, one for every room (run of free cells) along it."""
    if e1 - e0 <= 40:
        return
    if not corridor:
        place_door(a, orient, fixed, t, e0, e1, 16, (e0 + e1) // 2, 3)
        return
    line = np.zeros(len(side_line) + 2, np.int8)
    line[1:-1] = side_line[:] == FREE
    d = np.diff(line)
    starts, ends = np.nonzero(d == 1)[0], np.nonzero(d == -1)[0]
    for s0, s1 in zip(starts.tolist(), ends.tolist()):
        s0, s1 = max(s0, e0), min(s1, e1)
        if s1 - s0 >= 40:
            dw = int(rng.integers(12, 17))
            place_door(a, orient, fixed, t, s0, s1, dw, int(rng.integers(s0 + 5, s1 - dw - 4)), 3)


def bsp(rng, r0, c0, r1, c1, max_room, min_room, t, a, walls):
    """Recursively split the free rectangle [r0, r1) x [c0, c1) by walls of thickness t."""
    h, w = r1 - r0, c1 - c0
    if max(h, w) <= max_room:
        return
    if h >= w:
        lo, hi = r0 + min_room, r1 - min_room - t
        if hi <= lo:
            return
        r = int(rng.integers(lo, hi + 1))
        a[r:r + t, c0:c1] = OCC
        walls.append(("h", r, c0, c1))
        bsp(rng, r0, c0, r, c1, max_room, min_room, t, a, walls)
        bsp(rng, r + t, c0, r1, c1, max_room, min_room, t, a, walls)
    else:
        lo, hi = c0 + min_room, c1 - min_room - t
        if hi <= lo:
            return
        c = int(rng.integers(lo, hi + 1))
        a[r0:r1, c:c + t] = OCC
        walls.append(("v", c, r0, r1))
        bsp(rng, r0, c0, r1, c, max_room, min_room, t, a, walls)
        bsp(rng, r0, c + t, r1, c1, max_room, min_room, t, a, walls)


# ---------------------------------------------------------------------------
# scenario 4: cave
# ---------------------------------------------------------------------------

def make_cave():
    H = W = 900
    res = 0.05
    rng = np.random.default_rng(7031)
    cave = np.zeros((H, W), np.uint8)
    core = np.zeros((H, W), np.uint8)      # tunnel centre lines, 0.9 m wide: never closed by the noise
    # chambers: Poisson-disk centres, one forced near the west edge (the OC chamber)
    centres = [(450.0 + rng.uniform(-60, 60), 110.0)]
    radii = [70.0]
    tries = 0
    while len(centres) < 16 and tries < 5000:
        tries += 1
        r, c = rng.uniform(80, H - 80), rng.uniform(80, W - 80)
        if all((r - p) ** 2 + (c - q) ** 2 > 150 ** 2 for p, q in centres):
            centres.append((r, c))
            radii.append(float(rng.uniform(35, 85)))
    for (r, c), R in zip(centres, radii):
        rr0, rr1 = int(max(0, r - 1.5 * R)), int(min(H, r + 1.5 * R))
        cc0, cc1 = int(max(0, c - 1.5 * R)), int(min(W, c + 1.5 * R))
        yy, xx = np.mgrid[rr0:rr1, cc0:cc1]
        th = np.arctan2(yy - r, xx - c)
        rad = np.full(th.shape, R)
        for k in range(2, 6):
            rad = rad + R * rng.uniform(0.0, 0.12) * np.cos(k * th + rng.uniform(0, 2 * np.pi))
        cave[rr0:rr1, cc0:cc1][np.hypot(yy - r, xx - c) <= rad] = 1
    # tunnels: minimum spanning tree over the chambers plus a few loops
    n = len(centres)
    dist = np.array([[np.hypot(p[0] - q[0], p[1] - q[1]) for q in centres] for p in centres])
    in_tree, edges = {0}, []
    while len(in_tree) < n:
        best = None
        for i in in_tree:
            for j in range(n):
                if j not in in_tree and (best is None or dist[i, j] < dist[best[0], best[1]]):
                    best = (i, j)
        edges.append(best)
        in_tree.add(best[1])
    extra = sorted(((dist[i, j], i, j) for i in range(n) for j in range(i + 1, n)
                    if (i, j) not in edges and (j, i) not in edges))
    for _, i, j in extra[:3]:
        edges.append((i, j))

    def tunnel(r, c, tr, tc, stop, rad_lo, rad_hi):
        heading = np.arctan2(tr - r, tc - c)
        rad = (rad_lo + rad_hi) / 2
        for _ in range(2000):
            want = np.arctan2(tr - r, tc - c)
            turn = (want - heading + np.pi) % (2 * np.pi) - np.pi
            heading += 0.18 * turn + rng.normal(0, 0.28)
            r += 4.0 * np.sin(heading)
            c += 4.0 * np.cos(heading)
            r, c = min(max(r, 40), H - 40), min(max(c, 40), W - 40)
            rad = min(max(rad + rng.normal(0, 1.0), rad_lo), rad_hi)
            disk(cave, r, c, rad, 1)
            disk(core, r, c, 9, 1)
            if np.hypot(tr - r, tc - c) < stop:
                break

    for i, j in edges:
        (r, c), (tr, tc) = centres[i], centres[j]
        tunnel(r, c, tr, tc, radii[j] * 0.5, 10, 17)
    # dead-end side passages
    for _ in range(5):
        i = int(rng.integers(0, n))
        r, c = centres[i]
        ang = rng.uniform(0, 2 * np.pi)
        length = rng.uniform(120, 220)
        tunnel(r, c, r + length * np.sin(ang), c + length * np.cos(ang), 10, 10, 14)
    # rock pillars inside the large chambers
    for (r, c), R in zip(centres[1:], radii[1:]):
        if R > 55:
            for _ in range(3):
                ang, d = rng.uniform(0, 2 * np.pi), rng.uniform(0.3, 0.55) * R
                pr, pc, prad = r + d * np.sin(ang), c + d * np.cos(ang), rng.uniform(7, 12)
                m = int(prad) + 3                  # keep pillars off the tunnel cores
                if not core[int(pr) - m:int(pr) + m, int(pc) - m:int(pc) + m].any():
                    disk(cave, pr, pc, prad, 0)
    # organic walls: blur + low-frequency noise, threshold
    noise = rng.random((24, 24)).astype(np.float32)
    noise = np.asarray(Image.fromarray(noise, "F").resize((W, H), Image.BICUBIC), np.float64)
    fine = rng.random((150, 150)).astype(np.float32)
    fine = np.asarray(Image.fromarray(fine, "F").resize((W, H), Image.BICUBIC), np.float64)
    f = cave.astype(np.float64)
    for _ in range(2):
        f = box_blur(f, 4)
    free = (f + 0.3 * (noise - 0.5) + 0.25 * (fine - 0.5)) > 0.5
    free |= core.astype(bool)
    free[:12, :] = free[-12:, :] = False
    free[:, :12] = free[:, -12:] = False
    raw_free = int(free.sum())
    # keep what a round robot of 0.85 m diameter can sweep from the main component:
    # centres with 8.5 cells of clearance, largest 4-connected set, grown back by the disk
    rad = 8.5
    centres_ok = disk_erode(free, rad)
    lab, sizes = label4(centres_ok)
    main = lab == int(np.argmax(sizes[1:]) + 1)
    free = disk_dilate(main, rad) & free
    a = np.where(free, FREE, OCC).astype(np.uint8)
    # OC: centre of the west chamber, snapped to a cell with 1 m clearance
    oc_cell = snap_free(a, (int(centres[0][0]), int(centres[0][1])), 20)
    comment = ("cave/mine: %d organic chambers joined by meandering tunnels with dead ends and rock pillars, "
               "largest connected part only (%.1f%% of the raw free cells kept)" % (n, 100.0 * free.sum() / raw_free))
    return dict(a=a, res=res, origin=(-22.5, -22.5), oc_cell=oc_cell, comment=comment,
                oc_note="west chamber near the left edge")


def snap_free(a, cell, k):
    """Nearest cell to `cell` whose (2k+1)^2 neighbourhood is free."""
    ok = erode(a == FREE, k)
    rs, cs = np.nonzero(ok)
    if len(rs) == 0:
        raise MapError("no cell with the requested clearance")
    i = int(np.argmin((rs - cell[0]) ** 2 + (cs - cell[1]) ** 2))
    return int(rs[i]), int(cs[i])


# ---------------------------------------------------------------------------
# output, statistics and checks
# ---------------------------------------------------------------------------

SCENARIOS = [
    ("office", make_office),
    ("warehouse", make_warehouse),
    ("campus", make_campus),
    ("cave", make_cave),
]


def fmt(v):
    s = "%.3f" % v
    s = s.rstrip("0")
    return s + "0" if s.endswith(".") else s


def cell_to_world(H, res, origin, cell):
    r, c = cell
    return origin[0] + (c + 0.5) * res, origin[1] + (H - 1 - r + 0.5) * res


def world_to_cell(H, res, origin, x, y):
    import math
    return H - 1 - int(math.floor((y - origin[1]) / res)), int(math.floor((x - origin[0]) / res))


def check_and_stats(name, m):
    a, res, origin = m["a"], m["res"], m["origin"]
    H, W = a.shape
    vals = set(np.unique(a).tolist())
    if not vals <= {FREE, OCC, UNK}:
        raise MapError("%s: unexpected pixel values %s" % (name, sorted(vals)))
    free = a == FREE
    lab, sizes = label4(free)
    r, c = m["oc_cell"]
    if a[r, c] != FREE:
        raise MapError("%s: OC cell %s is not free" % (name, (r, c)))
    oc_label = lab[r, c]
    total = int(free.sum())
    reach = int(sizes[oc_label])
    # OC world coordinates as written to the scenario, converted back
    x, y = cell_to_world(H, res, origin, (r, c))
    xs, ys = fmt(x), fmt(y)
    back = world_to_cell(H, res, origin, float(xs), float(ys))
    if back != (r, c):
        raise MapError("%s: OC [%s, %s] converts back to cell %s, not %s" % (name, xs, ys, back, (r, c)))
    # robot fit: a round robot of 0.75 m diameter swept over the free space from the OC
    rad = 0.375 / res
    ok = disk_erode(free, rad)
    olab, osizes = label4(ok)
    sweep = disk_dilate(olab == olab[r, c], rad) & free if olab[r, c] else np.zeros_like(free)
    ulab, usizes = label4(free & ~sweep)
    unswept_max = int(usizes[1:].max()) if len(usizes) > 1 else 0
    if unswept_max * res * res > 0.5:
        rr, cc = np.nonzero(ulab == int(np.argmax(usizes[1:]) + 1))
        raise MapError("%s: a %.2f m2 patch around cell (row %d, col %d) is out of reach of a %.2f m robot"
                       % (name, unswept_max * res * res, rr[0], cc[0], 2 * rad * res))
    return dict(H=H, W=W, res=res, origin=origin, total=total, reach=reach, unswept_max=unswept_max,
                ncomp=len(sizes) - 1, oc=(xs, ys), oc_cell=(r, c), robot=2 * rad * res,
                sweep=int(sweep.sum()), fit_comps=len(osizes) - 1, lab=lab,
                free_m2=total * res * res, reach_m2=reach * res * res)


def write(name, m, st, outdir):
    a, res, origin = m["a"], m["res"], m["origin"]
    Image.fromarray(a, "L").save(os.path.join(outdir, name + ".png"), optimize=True)
    with open(os.path.join(outdir, name + ".yaml"), "w") as f:
        f.write("image: %s.png\n" % name)
        f.write("resolution: %s\n" % fmt(res))
        f.write("origin: [%s, %s, 0.0]\n" % (fmt(origin[0]), fmt(origin[1])))
        f.write("negate: 0\n")
        f.write("occupied_thresh: 0.65\n")
        f.write("free_thresh: 0.196\n")
        f.write("mode: trinary\n")
    H, W = a.shape
    with open(os.path.join(outdir, name + ".scenario.yaml"), "w") as f:
        f.write("# %s: %d x %d cells at %s m/cell = %s m x %s m; %s; OC in the %s\n"
                % (name, W, H, fmt(res), fmt(W * res), fmt(H * res), m["comment"], m["oc_note"]))
        f.write("map: %s.yaml\n" % name)
        f.write("oc: [%s, %s]\n" % st["oc"])
        f.write("team:\n  agents: 20\n  speed: 0.5\n")
        f.write("radio:\n"
                "  tx_power_dbm: 0.0\n"
                "  ref_loss_db: 40.0\n"
                "  exponent: 3.0\n"
                "  wall_loss_db: 5.0\n"
                "  max_walls: 4\n"
                "  sensitivity_dbm: -75.0\n")
        f.write("mission:\n  goals_per_request: 40\n  cycles: 10\n  seed: 1\n")
        f.write("planner:\n  methods: [bap, pap, rap]\n  collectors: [0, 8]\n  alpha: 0.5\n  beta: 0.5\n")


def main(argv):
    outdir = os.path.dirname(os.path.abspath(__file__))
    names = []
    i = 0
    while i < len(argv):
        if argv[i] == "--outdir":
            outdir = argv[i + 1]
            i += 2
        elif argv[i] in ("-h", "--help"):
            print(__doc__)
            return 0
        else:
            names.append(argv[i])
            i += 1
    known = dict(SCENARIOS)
    for n in names:
        if n not in known:
            print("generate.py: unknown scenario '%s' (known: %s)" % (n, ", ".join(known)), file=sys.stderr)
            return 2
    os.makedirs(outdir, exist_ok=True)
    for name, make in SCENARIOS:
        if names and name not in names:
            continue
        m = make()
        st = check_and_stats(name, m)
        if st["reach"] < 0.999 * st["total"]:
            raise MapError("%s: only %.3f%% of the free space is reachable from the OC" %
                           (name, 100.0 * st["reach"] / st["total"]))
        # free pockets cut off from the OC (e.g. between overlapping tree trunks) become obstacles
        pockets = (st["lab"] != st["lab"][st["oc_cell"]]) & (m["a"] == FREE)
        filled = int(pockets.sum())
        if filled:
            m["a"][pockets] = OCC
            st2 = check_and_stats(name, m)
            assert st2["reach"] == st2["total"] == st["reach"]
        write(name, m, st, outdir)
        print("%s: %d x %d cells at %s m/cell = %s m x %s m" % (
            name, st["W"], st["H"], fmt(st["res"]), fmt(st["W"] * st["res"]), fmt(st["H"] * st["res"])))
        print("  free space: %d cells = %.1f m2 (%.1f%% of the map) in %d 4-connected component%s" % (
            st["total"], st["free_m2"], 100.0 * st["total"] / (st["W"] * st["H"]),
            st["ncomp"], "" if st["ncomp"] == 1 else "s"))
        print("  reachable from the OC: %d cells = %.1f m2 = %.4f%% of the free space%s" % (
            st["reach"], st["reach_m2"], 100.0 * st["reach"] / st["total"],
            "; the other %d cells (pockets) were filled as obstacles" % filled if filled else ""))
        print("  a round robot of %.2f m diameter sweeps %.2f%% of the free space (largest patch it misses: %.3f m2)"
              % (st["robot"], 100.0 * st["sweep"] / st["total"], st["unswept_max"] * st["res"] ** 2))
        print("  OC: [%s, %s] m = cell (row %d, col %d), origin [%s, %s]" % (
            st["oc"][0], st["oc"][1], st["oc_cell"][0], st["oc_cell"][1],
            fmt(st["origin"][0]), fmt(st["origin"][1])))
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except MapError as e:
        print("generate.py: %s" % e, file=sys.stderr)
        sys.exit(1)
