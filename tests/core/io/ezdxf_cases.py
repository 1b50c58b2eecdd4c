"""DXF files for the DXF reader's tests, written by ezdxf (an independent DXF library), with ezdxf's own flattening of
every entity (blocks expanded) as the oracle: python3 ezdxf_cases.py OUT_DIR.  With --check FILE.dxf it instead reads a
DXF popcut wrote, audits it and prints its lines per layer as JSON."""
import json
import math
import sys

import ezdxf
from ezdxf import disassemble


def flat(e):
    """WCS points within 0.0005 of the entity, by ezdxf's own exact curve evaluation (not its Bezier paths, which
    approximate arcs to 3e-4 of the radius)."""
    kind = e.dxftype()
    if kind == "LINE":
        return [e.dxf.start, e.dxf.end]
    if kind in ("ARC", "CIRCLE"):
        return list(e.flattening(0.0005))
    if kind in ("ELLIPSE", "SPLINE"):
        return list(e.flattening(0.0005, segments=16))
    if kind == "LWPOLYLINE":
        pts = []
        for part in e.virtual_entities():
            pts += flat(part)
        return pts
    raise TypeError(kind)


def oracle(doc, scale):
    """Every entity of the model space, inserts expanded, as dense WCS points in mm, in file order."""
    out = []
    for e in disassemble.recursive_decompose(doc.modelspace()):
        if e.dxftype() == "TEXT":
            continue
        pts = [[v.x * scale, v.y * scale] for v in flat(e)]
        out.append({"type": e.dxftype(), "layer": e.dxf.layer, "points": pts})
    return out


def shapes(out_dir):
    doc = ezdxf.new("R2010", setup=True)
    doc.units = ezdxf.units.MM
    for name, colour, linetype in [("CUT", 7, "CONTINUOUS"), ("VALLEY", 5, "DASHED"), ("Layer1", 2, "CONTINUOUS")]:
        doc.layers.add(name, color=colour, linetype=linetype)
    msp = doc.modelspace()
    msp.add_line((0, 0), (40, 0), dxfattribs={"layer": "CUT"})
    # A slot with round ends: bulge 1 is a half circle.
    msp.add_lwpolyline([(10, 10, 1), (10, 20, 0), (30, 20, 1), (30, 10, 0)], format="xyb", close=True,
                       dxfattribs={"layer": "CUT"})
    msp.add_lwpolyline([(50, 0, -0.4), (70, 5, 0.25), (80, 20)], format="xyb", dxfattribs={"layer": "CUT"})
    msp.add_arc((60, 40), 12, 30, 250, dxfattribs={"layer": "CUT"})
    msp.add_arc((90, 40), 8, 10, 120, dxfattribs={"layer": "CUT", "extrusion": (0, 0, -1)})
    msp.add_circle((100, 10), 6.5, dxfattribs={"layer": "CUT"})
    msp.add_ellipse((120, 40), major_axis=(15, 8), ratio=0.4, start_param=0.3, end_param=4.0,
                    dxfattribs={"layer": "CUT"})
    msp.add_ellipse((150, 40), major_axis=(0, 10), ratio=0.6, dxfattribs={"layer": "CUT"})
    msp.add_ellipse((150, 70), major_axis=(9, 3), ratio=0.5, start_param=0.5, end_param=2.5,
                    dxfattribs={"layer": "CUT", "extrusion": (0, 0, -1)})
    msp.add_open_spline([(0, 60), (10, 80), (25, 50), (40, 75), (55, 60)], degree=3, dxfattribs={"layer": "CUT"})
    s = math.sqrt(0.5)
    msp.add_rational_spline([(100, 80), (100, 100), (80, 100)], [1, s, 1], degree=2, dxfattribs={"layer": "CUT"})
    tab = doc.blocks.new("TAB", base_point=(5, 0))
    tab.add_line((0, 0), (10, 0), dxfattribs={"layer": "0"})
    tab.add_arc((5, 0), 5, 0, 180, dxfattribs={"layer": "CUT"})
    msp.add_blockref("TAB", (20, 120), dxfattribs={"layer": "VALLEY", "rotation": 30, "xscale": 2, "yscale": 0.5})
    grid = msp.add_blockref("TAB", (60, 120), dxfattribs={"layer": "CUT"})
    grid.grid(size=(2, 3), spacing=(15, 20))
    pair = doc.blocks.new("PAIR")
    pair.add_blockref("TAB", (0, 0), dxfattribs={"layer": "0"})
    pair.add_blockref("TAB", (0, 10), dxfattribs={"layer": "0", "rotation": 90})
    msp.add_blockref("PAIR", (150, 120), dxfattribs={"layer": "CUT", "rotation": -15})
    # Conventions without layer names: linetype, then colour.
    msp.add_line((0, 150), (30, 150), dxfattribs={"layer": "Layer1", "linetype": "DASHED"})
    msp.add_line((0, 155), (30, 155), dxfattribs={"layer": "Layer1", "linetype": "DASHDOT"})
    msp.add_line((0, 160), (30, 160), dxfattribs={"layer": "Layer1", "color": 1})
    msp.add_line((0, 165), (30, 165), dxfattribs={"layer": "Layer1"})
    msp.add_text("not cut", dxfattribs={"layer": "CUT"})
    doc.saveas(f"{out_dir}/shapes.dxf")
    with open(f"{out_dir}/shapes.json", "w") as f:
        json.dump(oracle(doc, 1.0), f)


def step(out_dir, units, scale):
    """The one-step pop-up of examples/drawn/step.svg as a CAD dieline, in the given units."""
    doc = ezdxf.new("R2000")
    doc.units = units
    for name in ["CUT", "MOUNTAIN", "VALLEY", "OUTLINE"]:
        doc.layers.add(name)
    msp = doc.modelspace()
    k = 1.0 / scale  # drawing units per mm
    def line(a, b, layer):
        msp.add_line((a[0] * k, a[1] * k), (b[0] * k, b[1] * k), dxfattribs={"layer": layer})
    msp.add_lwpolyline([(0, 0), (100 * k, 0), (100 * k, 120 * k), (0, 120 * k)], close=True,
                       dxfattribs={"layer": "OUTLINE"})
    for x in (30, 70):
        line((x, 40), (x, 80), "CUT")
    line((0, 60), (30, 60), "VALLEY")
    line((70, 60), (100, 60), "VALLEY")
    line((30, 40), (70, 40), "VALLEY")
    line((30, 80), (70, 80), "VALLEY")
    line((30, 60), (70, 60), "MOUNTAIN")
    return doc


def box(out_dir):
    """The tuck-lid box of examples/drawn/box.svg as a CAD dieline in inches, y up: CUT and CREASE layers."""
    doc = ezdxf.new("R2000")
    doc.units = ezdxf.units.IN
    for name in ["CUT", "CREASE"]:
        doc.layers.add(name)
    msp = doc.modelspace()
    def p(x, y):
        return (x / 25.4, (195 - y) / 25.4)
    outline = [(32, 0), (108, 0), (110, 15), (110, 77), (122, 80), (122, 100), (110, 103), (110, 105), (140, 105),
               (140, 165), (110, 165), (110, 167), (122, 170), (122, 190), (110, 193), (110, 195), (30, 195),
               (30, 193), (18, 190), (18, 170), (30, 167), (30, 165), (0, 165), (0, 105), (30, 105), (30, 103),
               (18, 100), (18, 80), (30, 77), (30, 15)]
    msp.add_lwpolyline([p(*q) for q in outline], close=True, dxfattribs={"layer": "CUT"})
    for a, b in [((30, 15), (110, 15)), ((30, 75), (110, 75)), ((30, 105), (110, 105)), ((30, 165), (110, 165)),
                 ((30, 105), (30, 165)), ((110, 105), (110, 165)), ((30, 77), (30, 103)), ((110, 77), (110, 103)),
                 ((30, 167), (30, 193)), ((110, 167), (110, 193))]:
        msp.add_line(p(*a), p(*b), dxfattribs={"layer": "CREASE"})
    doc.saveas(f"{out_dir}/box-in.dxf")


def cyclic(out_dir):
    doc = ezdxf.new("R2000")
    a = doc.blocks.new("A")
    b = doc.blocks.new("B")
    a.add_line((0, 0), (1, 0))
    a.add_blockref("B", (1, 1))
    b.add_blockref("A", (2, 2))
    doc.modelspace().add_blockref("A", (0, 0))
    doc.saveas(f"{out_dir}/cyclic.dxf")


def check(dxf_path):
    doc = ezdxf.readfile(dxf_path)
    auditor = doc.audit()
    layers = {}
    for e in doc.modelspace():
        layers.setdefault(e.dxf.layer, {}).setdefault(e.dxftype(), 0)
        layers[e.dxf.layer][e.dxftype()] += 1
    print(json.dumps({"errors": [str(x.message) for x in auditor.errors], "units": doc.units,
                      "layers": layers, "linetypes": {l.dxf.name: l.dxf.linetype for l in doc.layers}}))


if __name__ == "__main__":
    if sys.argv[1] == "--check":
        check(sys.argv[2])
        sys.exit(0)
    out = sys.argv[1]
    shapes(out)
    step(out, ezdxf.units.MM, 1.0).saveas(f"{out}/step-mm.dxf")
    step(out, ezdxf.units.IN, 25.4).saveas(f"{out}/step-in.dxf")
    unitless = step(out, 0, 1.0)
    unitless.header["$INSUNITS"] = 0
    unitless.saveas(f"{out}/step-unitless.dxf")
    cyclic(out)
    box(out)
