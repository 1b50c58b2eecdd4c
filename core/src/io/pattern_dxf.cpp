// DXF writer through dxflib: the pattern as layered lines (CUT, MOUNTAIN, VALLEY, OUTLINE) in mm for CAD and cutter
// software.
#include <dl_dxf.h>
#include <dl_writer_ascii.h>

#include <algorithm>
#include <charconv>
#include <iomanip>
#include <ostream>

#include "popcut/io/pattern_io.h"

namespace popcut {
namespace {

// dxflib's table and entity writers take its file writer; this one sends the same group pairs
// to a stream instead (no file is opened: the base's file name is empty), so the pattern
// streams like every other writer's output.
class StreamWriter final : public DL_WriterA {
 public:
  explicit StreamWriter(std::ostream& out) : DL_WriterA("", DL_Codes::AC1015), out_(out) {}

  void dxfReal(int gc, double value) const override {
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, value == 0 ? 0.0 : value).ptr;  // no "-0"
    code(gc) << std::string_view(text, static_cast<std::size_t>(end - text)) << '\n';
  }
  void dxfInt(int gc, int value) const override { code(gc) << value << '\n'; }
  void dxfHex(int gc, int value) const override {
    code(gc) << std::uppercase << std::hex << value << std::dec << std::nouppercase << '\n';
  }
  void dxfString(int gc, const char* value) const override { code(gc) << value << '\n'; }
  void dxfString(int gc, const std::string& value) const override { code(gc) << value << '\n'; }

 private:
  std::ostream& code(int gc) const { return out_ << std::setw(3) << gc << '\n'; }
  std::ostream& out_;
};

struct LayerSpec {
  const char* name;
  int colour;  // AutoCAD colour index
  const char* linetype;
};

// The reader's conventions, so the file reads back by layer name, and by linetype and colour
// in software that ignores layer names: cut black (7), mountain red dash-dot, valley blue dashed.
constexpr LayerSpec kLayers[] = {
    {"CUT", 7, "CONTINUOUS"}, {"MOUNTAIN", 1, "DASHDOT"}, {"VALLEY", 5, "DASHED"}, {"OUTLINE", 8, "CONTINUOUS"}};

void write_tables(DL_Dxf& dxf, StreamWriter& dw) {
  dw.sectionTables();
  dxf.writeVPort(dw);
  double dashed[] = {4.0, -2.0};
  double dashdot[] = {4.0, -1.5, 0.0, -1.5};
  dw.tableLinetypes(5);
  dxf.writeLinetype(dw, DL_LinetypeData("BYBLOCK", "", 0, 0, 0.0));
  dxf.writeLinetype(dw, DL_LinetypeData("BYLAYER", "", 0, 0, 0.0));
  dxf.writeLinetype(dw, DL_LinetypeData("CONTINUOUS", "Solid line", 0, 0, 0.0));
  dxf.writeLinetype(dw, DL_LinetypeData("DASHED", "Dashed __ __ __ (valley folds)", 0, 2, 6.0, dashed));
  dxf.writeLinetype(dw, DL_LinetypeData("DASHDOT", "Dash dot __ . __ . (mountain folds)", 0, 4, 7.0, dashdot));
  dw.tableEnd();
  dw.tableLayers(1 + static_cast<int>(std::size(kLayers)));
  dxf.writeLayer(dw, DL_LayerData("0", 0), DL_Attributes("", 7, 0, "CONTINUOUS", 1.0));
  for (const LayerSpec& l : kLayers)
    dxf.writeLayer(dw, DL_LayerData(l.name, 0), DL_Attributes("", l.colour, 0, l.linetype, 1.0));
  dw.tableEnd();
  dw.tableStyle(1);
  dxf.writeStyle(dw, DL_StyleData("Standard", 0, 0.0, 1.0, 0.0, 0, 2.5, "txt", ""));
  dw.tableEnd();
  dxf.writeView(dw);
  dxf.writeUcs(dw);
  dw.tableAppid(1);
  dxf.writeAppid(dw, "ACAD");
  dw.tableEnd();
  dxf.writeDimStyle(dw, 1, 1, 1, 1, 1);
  dxf.writeBlockRecord(dw);
  dw.tableEnd();
  dw.sectionEnd();
}

void write_blocks(DL_Dxf& dxf, StreamWriter& dw) {
  dw.sectionBlocks();
  for (const char* name : {"*Model_Space", "*Paper_Space", "*Paper_Space0"}) {
    dxf.writeBlock(dw, DL_BlockData(name, 0, 0.0, 0.0, 0.0));
    dxf.writeEndBlock(dw, name);
  }
  dw.sectionEnd();
}

}  // namespace

void write_pattern_dxf(std::ostream& out, const Pattern& p) {
  DL_Dxf dxf;
  StreamWriter dw(out);
  // dxflib's writeHeader fixes $HANDSEED at FFFF; a pattern of more lines than that would get
  // handles past the seed, so the seed is set above every handle this file uses.
  dw.dxfString(999, "popcut (dxflib)");
  dw.sectionHeader();
  dw.dxfString(9, "$ACADVER");
  dw.dxfString(1, "AC1015");
  dw.dxfString(9, "$HANDSEED");
  dw.dxfHex(5, static_cast<int>(std::min<std::size_t>(0x10000 + 2 * p.lines.size(), 0x7fffffff)));
  dw.dxfString(9, "$INSUNITS");
  dw.dxfInt(70, 4);  // millimetres
  dw.dxfString(9, "$MEASUREMENT");
  dw.dxfInt(70, 1);  // metric
  dw.sectionEnd();
  write_tables(dxf, dw);
  write_blocks(dxf, dw);
  dw.sectionEntities();
  const Point2 o = p.sheet.min;
  const double w = p.sheet.max.x_mm - o.x_mm, h = p.sheet.max.v_mm - o.v_mm;
  const DL_Attributes outline("OUTLINE", 256, -1, "BYLAYER", 1.0);
  dxf.writePolyline(dw, DL_PolylineData(4, 0, 0, 1), outline);
  for (const Point2 q : {Point2{0, 0}, Point2{w, 0}, Point2{w, h}, Point2{0, h}})
    dxf.writeVertex(dw, DL_VertexData(q.x_mm, q.v_mm, 0, 0));
  dxf.writePolylineEnd(dw);
  for (const Segment& s : p.lines) {
    const char* layer = s.kind == LineKind::cut ? "CUT" : s.kind == LineKind::mountain ? "MOUNTAIN" : "VALLEY";
    dxf.writeLine(dw, DL_LineData(s.a.x_mm - o.x_mm, s.a.v_mm - o.v_mm, 0, s.b.x_mm - o.x_mm, s.b.v_mm - o.v_mm, 0),
                  DL_Attributes(layer, 256, -1, "BYLAYER", 1.0));
  }
  dw.sectionEnd();
  dxf.writeObjects(dw);
  dxf.writeObjectsEnd(dw);
  dw.dxfEOF();
}

}  // namespace popcut
