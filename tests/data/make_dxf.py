#!/usr/bin/env python3
"""Writes the DXF test drawings of tests/dxf_file.rs with ezdxf (1.4.5).

    pip install ezdxf && python3 tests/data/make_dxf.py

CI does not run this: the .dxf files it writes are committed beside it. Every
shape sits on its own layer, so a test can read one with `shape.layer`; the
areas the tests compare with are analytic, except the two splines', which this
script measures with ezdxf's own NURBS evaluator (shoelace over 200 000 points)
and prints, for the constants in tests/dxf_file.rs.

Files:
- dxf-entities.dxf   $INSUNITS = 4 (mm): every entity pfcam reads.
- dxf-inches.dxf     $INSUNITS = 1 (in): a 1 x 0.5 in rectangle with a hole.
- dxf-unitless.dxf   $INSUNITS = 0: the same drawing, taken as mm.
- dxf-open.dxf       an open chain of LINEs and an ARC (an error).
- dxf-huge.dxf       a 5 m square (past any job's size bound).
- ../../jobs/dxf-plate.dxf  the drawing of jobs/dxf-plate.toml.
"""
import math
import os

import ezdxf
from ezdxf.math import BSpline

HERE = os.path.dirname(os.path.abspath(__file__))


def shoelace(points):
    a = 0.0
    for (x0, y0), (x1, y1) in zip(points, points[1:] + points[:1]):
        a += x0 * y1 - x1 * y0
    return a / 2.0


def new_doc(insunits):
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = insunits
    return doc


def lines(msp, corners, layer):
    n = len(corners)
    for i in range(n):
        msp.add_line(corners[i], corners[(i + 1) % n], dxfattribs={"layer": layer})


def closed_spline(msp, layer):
    """A periodic (unclamped, uniform knots) rational cubic, closed: the
    control points wrap around by the degree. Returns its area by ezdxf."""
    ctrl = [(140, 30), (155, 28), (162, 40), (152, 52), (138, 50), (132, 40)]
    w = [1.0, 2.0, 0.5, 1.5, 1.0, 3.0]
    p = 3
    cw = ctrl + ctrl[:p]
    ww = w + w[:p]
    knots = [float(i) for i in range(len(cw) + p + 1)]
    curve = BSpline(cw, order=p + 1, knots=knots, weights=ww)
    s = msp.add_spline(dxfattribs={"layer": layer})
    s.apply_construction_tool(curve)
    s.closed = True  # flag 1; ezdxf also sets the periodic flag 2
    s.dxf.flags = s.dxf.flags | 2 | 4  # periodic, rational
    t0, t1 = knots[p], knots[len(cw)]
    n = 200_000
    pts = [curve.point(t0 + (t1 - t0) * i / n) for i in range(n)]
    return shoelace([(q.x, q.y) for q in pts])


def open_spline(msp, layer):
    """A clamped cubic (the curve starts and ends at its end control points),
    closed by a LINE. Returns the area by ezdxf."""
    ctrl = [(175, 30), (195, 25), (200, 45), (185, 55), (172, 48)]
    s = msp.add_open_spline(ctrl, degree=3, dxfattribs={"layer": layer})
    msp.add_line(ctrl[-1], ctrl[0], dxfattribs={"layer": layer})
    tool = s.construction_tool()
    n = 200_000
    t_max = tool.max_t
    pts = [tool.point(t_max * i / n) for i in range(n + 1)]
    return shoelace([(q.x, q.y) for q in pts])


def tab_block(doc):
    """Block TAB, base point (5, 3): a 10 x 6 rectangle with a round hole r 1.5
    at its middle, both on layer 0 (they take the layer of their INSERT)."""
    blk = doc.blocks.new("TAB", base_point=(5, 3))
    blk.add_lwpolyline([(0, 0), (10, 0), (10, 6), (0, 6)], close=True)
    blk.add_circle((5, 3), 1.5)
    pair = doc.blocks.new("PAIR")
    pair.add_blockref("TAB", (0, 0))
    pair.add_blockref("TAB", (20, 0), dxfattribs={"xscale": -1, "rotation": 90})


def entities():
    doc = new_doc(4)
    msp = doc.modelspace()
    # CIRCLE r 10: 100 pi.
    msp.add_circle((0, 0), 10, dxfattribs={"layer": "CIRCLE"})
    # LINES: a 30 x 20 rectangle, drawn out of order, both directions, with a
    # 0.004 mm gap at one corner (along the edge, so the area stays 600).
    L = {"layer": "LINES"}
    msp.add_line((50, 10), (50, -10), dxfattribs=L)
    msp.add_line((20, 10), (50, 10), dxfattribs=L)
    msp.add_line((20, -10), (50.004, -10), dxfattribs=L)
    msp.add_line((20, -10), (20, 10), dxfattribs=L)
    # LWPOLY: stadium, 30 straight, radius 8 (bulge 1 = half circle): 480 + 64 pi.
    msp.add_lwpolyline(
        [(60, -8, 0, 0, 0), (90, -8, 0, 0, 1), (90, 8, 0, 0, 0), (60, 8, 0, 0, 1)],
        format="xyseb", close=True, dxfattribs={"layer": "LWPOLY"})
    # POLYLINE (the old 2D form): 40 x 20 rectangle, corners r 5 by bulges
    # tan(90 deg / 4): 800 - (4 - pi) 25.
    b = math.tan(math.pi / 8)
    pts = [(105, -10, 0, 0, 0), (135, -10, 0, 0, b), (140, -5, 0, 0, 0), (140, 5, 0, 0, b),
           (135, 10, 0, 0, 0), (105, 10, 0, 0, b), (100, 5, 0, 0, 0), (100, -5, 0, 0, b)]
    msp.add_polyline2d(pts, format="xyseb", close=True, dxfattribs={"layer": "POLYLINE"})
    # SLOT: two ARCs and two LINEs, centres (0, 40), (25, 40), r 5: 250 + 25 pi.
    # The right ARC is written in a mirrored OCS (extrusion 0, 0, -1).
    S = {"layer": "SLOT"}
    msp.add_line((0, 35), (25, 35), dxfattribs=S)
    msp.add_line((25, 45), (0, 45), dxfattribs=S)
    msp.add_arc((0, 40), 5, 90, 270, dxfattribs=S)
    msp.add_arc((-25, 40), 5, 90, 270, dxfattribs={**S, "extrusion": (0, 0, -1)})
    # ELLIPSE a 15, b 7.5, turned 30 deg: 112.5 pi.
    c30, s30 = math.cos(math.pi / 6), math.sin(math.pi / 6)
    msp.add_ellipse((60, 40), (15 * c30, 15 * s30, 0), 0.5, dxfattribs={"layer": "ELLIPSE"})
    # HALF_ELLIPSE: a 10, b 6, parameters 0 to pi, closed by a LINE: 30 pi.
    msp.add_ellipse((100, 40), (10, 0, 0), 0.6, 0, math.pi, dxfattribs={"layer": "HALF_ELLIPSE"})
    msp.add_line((90, 40), (110, 40), dxfattribs={"layer": "HALF_ELLIPSE"})
    a_closed = closed_spline(msp, "SPLINE")
    a_open = open_spline(msp, "SPLINE_OPEN")
    # INSERT of TAB at (0, 80), x scale 2, y scale 1.5, turned 30 deg: the
    # hole becomes an ellipse 3 x 2.25: (60 - 2.25 pi) * 3.
    tab_block(doc)
    msp.add_blockref("TAB", (0, 80), dxfattribs={
        "layer": "INSERT", "xscale": 2, "yscale": 1.5, "rotation": 30})
    # NESTED: PAIR (TAB, and TAB mirrored and turned) at (40, 80), scale 0.5,
    # turned -15 deg: 2 * 0.25 * (60 - 2.25 pi).
    msp.add_blockref("PAIR", (40, 80), dxfattribs={
        "layer": "NESTED", "xscale": 0.5, "yscale": 0.5, "rotation": -15})
    # HOLE: a 20 x 20 square with a round hole r 5 and an island r 2 in it:
    # 400 - 25 pi + 4 pi.
    msp.add_lwpolyline([(100, 70), (120, 70), (120, 90), (100, 90)], close=True,
                       dxfattribs={"layer": "HOLE"})
    msp.add_circle((110, 80), 5, dxfattribs={"layer": "HOLE"})
    msp.add_circle((110, 80), 2, dxfattribs={"layer": "HOLE"})
    # BOWTIE: a closed LWPOLYLINE crossing itself: two triangles of 100.
    msp.add_lwpolyline([(140, 70), (160, 90), (160, 70), (140, 90)], close=True,
                       dxfattribs={"layer": "BOWTIE"})
    # EMPTY: a layer in the table with nothing on it.
    doc.layers.add("EMPTY")
    # TEXT on layer NOTES: not material, ignored.
    msp.add_text("not material", dxfattribs={"layer": "NOTES", "height": 3}).set_placement((0, -30))
    doc.saveas(os.path.join(HERE, "dxf-entities.dxf"))
    print(f"SPLINE (closed periodic rational cubic) area by ezdxf: {a_closed:.9f}")
    print(f"SPLINE_OPEN (clamped cubic + LINE) area by ezdxf: {a_open:.9f}")


def inches(insunits, name):
    doc = new_doc(insunits)
    msp = doc.modelspace()
    msp.add_lwpolyline([(0, 0), (1, 0), (1, 0.5), (0, 0.5)], close=True)
    msp.add_circle((0.5, 0.25), 0.125)
    doc.saveas(os.path.join(HERE, name))


def open_chain():
    doc = new_doc(4)
    msp = doc.modelspace()
    msp.add_line((0, 0), (10, 0))
    msp.add_line((10, 0), (10, 10))
    msp.add_arc((5, 10), 5, 0, 90)  # (10, 10) to (5, 15); nothing returns to (0, 0)
    msp.add_circle((30, 0), 3)
    doc.saveas(os.path.join(HERE, "dxf-open.dxf"))


def huge():
    doc = new_doc(4)
    lines(doc.modelspace(), [(0, 0), (5000, 0), (5000, 5000), (0, 5000)], "0")
    doc.saveas(os.path.join(HERE, "dxf-huge.dxf"))


def plate():
    """jobs/dxf-plate.dxf, $INSUNITS = 4: a 40 x 24 mm plate whose outline is
    an LWPOLYLINE with 4 mm corner bulges, two mounting holes (an INSERT of a
    block HOLE, r 2.5, twice), and a slot of two ARCs and two
    LINEs; a text on layer NOTES is not material."""
    doc = new_doc(4)
    msp = doc.modelspace()
    b = math.tan(math.pi / 8)
    r = 4
    msp.add_lwpolyline(
        [(r, 0, 0, 0, 0), (40 - r, 0, 0, 0, b), (40, r, 0, 0, 0), (40, 24 - r, 0, 0, b),
         (40 - r, 24, 0, 0, 0), (r, 24, 0, 0, b), (0, 24 - r, 0, 0, 0), (0, r, 0, 0, b)],
        format="xyseb", close=True, dxfattribs={"layer": "PLATE"})
    hole = doc.blocks.new("HOLE")
    hole.add_circle((0, 0), 2.5)
    for x in (7, 33):
        msp.add_blockref("HOLE", (x, 17), dxfattribs={"layer": "PLATE"})
    S = {"layer": "PLATE"}
    msp.add_line((14, 5), (26, 5), dxfattribs=S)
    msp.add_arc((26, 8), 3, 270, 90, dxfattribs=S)
    msp.add_line((26, 11), (14, 11), dxfattribs=S)
    msp.add_arc((14, 8), 3, 90, 270, dxfattribs=S)
    msp.add_text("pfcam DXF plate", dxfattribs={"layer": "NOTES", "height": 2}).set_placement((0, -5))
    doc.saveas(os.path.join(HERE, "..", "..", "jobs", "dxf-plate.dxf"))


if __name__ == "__main__":
    entities()
    inches(1, "dxf-inches.dxf")
    inches(0, "dxf-unitless.dxf")
    open_chain()
    huge()
    plate()
