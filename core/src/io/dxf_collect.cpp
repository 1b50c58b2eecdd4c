// dxflib's callbacks gathered into shapes, blocks and layers, each shape named by its line in the file.
#include "io/dxf_collect.h"

#include <dl_creationadapter.h>
#include <dl_dxf.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <sstream>

#include "io/ascii_case.h"
#include "popcut/error.h"
#include "popcut/text.h"

namespace popcut::dxf {
namespace {

constexpr double kPi = std::numbers::pi;

// The counter-clockwise sweep from a start to an end angle, in (0, full]: equal angles are a
// whole turn, as DXF draws them.
double sweep(double difference, double full) {
  const double d = std::fmod(difference, full);
  return d <= 0 ? d + full : d;
}

// dxflib's callbacks, collecting shapes into the model or the block being defined.
class Collector final : public DL_CreationAdapter {
 public:
  Collector(const Scan& scan, const std::string& source) : source_(source) {
    for (const EntityPlace& e : scan.entities) places_[e.type == "LWPOLYLINE" ? "POLYLINE" : e.type].push_back(e);
  }

  Collected out;

  void addLayer(const DL_LayerData& d) override {
    const DL_Attributes a = getAttributes();
    out.layers[ascii_upper(d.name)] = {std::abs(a.getColor()), ascii_upper(a.getLinetype()),
                                       d.off || a.getColor() < 0 || (d.flags & 1)};
  }
  void addBlock(const DL_BlockData& d) override {
    block_ = &out.blocks[d.name];
    block_->base = {d.bpx, d.bpy};
  }
  void endBlock() override { block_ = nullptr; }

  void addLine(const DL_LineData& d) override {
    Shape& s = start(Shape::Type::path, "LINE", false);
    s.vertices = {{{d.x1, d.y1}, 0}, {{d.x2, d.y2}, 0}};
  }
  void addArc(const DL_ArcData& d) override {
    Shape& s = start(Shape::Type::ellipse, "ARC", true);
    s.centre = {d.cx, d.cy};
    s.major = {d.radius, 0};
    s.t0 = std::fmod(d.angle1, 360) * kPi / 180;  // a huge angle keeps its precision
    s.t1 = s.t0 + sweep(d.angle2 - d.angle1, 360) * kPi / 180;
  }
  void addCircle(const DL_CircleData& d) override {
    Shape& s = start(Shape::Type::ellipse, "CIRCLE", true);
    s.centre = {d.cx, d.cy};
    s.major = {d.radius, 0};
    s.closed = true;
  }
  void addEllipse(const DL_EllipseData& d) override {
    // WCS: the extrusion only turns the minor axis (mirrored = clockwise parameter).
    Shape& s = start(Shape::Type::ellipse, "ELLIPSE", false);
    s.centre = {d.cx, d.cy};
    s.major = {d.mx, d.my};
    s.ratio = d.ratio;
    s.t0 = std::fmod(d.angle1, 2 * kPi);
    s.t1 = s.t0 + sweep(d.angle2 - d.angle1, 2 * kPi);
    s.closed = s.t1 - s.t0 > 2 * kPi - 1e-9;
  }
  void addPolyline(const DL_PolylineData& d) override {
    Shape& s = start(Shape::Type::path, "POLYLINE", true);
    s.closed = d.flags & 1;
    if (d.flags & (16 | 64)) fail(s.where, "a polygon or polyface mesh, not a line: explode it into lines first");
  }
  void addVertex(const DL_VertexData& d) override {
    if (Shape* s = last(Shape::Type::path)) s->vertices.push_back({{d.x, d.y}, d.bulge});
  }
  void addSpline(const DL_SplineData& d) override {
    Shape& s = start(Shape::Type::spline, "SPLINE", false);
    s.degree = static_cast<int>(d.degree);
    s.closed = d.flags & 1;
  }
  void addControlPoint(const DL_ControlPointData& d) override {
    if (Shape* s = last(Shape::Type::spline)) {
      s->control.push_back({d.x, d.y});
      s->weights.push_back(d.w);
    }
  }
  void addKnot(const DL_KnotData& d) override {
    if (Shape* s = last(Shape::Type::spline)) s->knots.push_back(d.k);
  }
  void addFitPoint(const DL_FitPointData&) override {
    if (Shape* s = last(Shape::Type::spline)) ++s->fit_points;
  }
  void addInsert(const DL_InsertData& d) override {
    Shape& s = start(Shape::Type::insert, "INSERT", true);
    s.block = d.name;
    s.at = {d.ipx, d.ipy};
    s.sx = d.sx;
    s.sy = d.sy;
    s.angle_deg = d.angle;
    s.columns = d.cols;
    s.rows = d.rows;
    s.column_mm = d.colSp;
    s.row_mm = d.rowSp;
  }

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& message) const {
    throw Error(ErrorCode::invalid_input, source_, where, message);
  }

  Shape& start(Shape::Type type, const char* kind, bool ocs) {
    auto& queue = places_[kind];
    const DL_Attributes a = getAttributes();
    Shape s;
    s.type = type;
    s.style = {a.getLayer().empty() ? "0" : a.getLayer(), a.getColor(), ascii_upper(a.getLinetype())};
    const std::string type_name = queue.empty() ? kind : queue.front().type;
    s.where = (queue.empty() ? "" : "line " + std::to_string(queue.front().line) + ", ") + type_name +
              (queue.empty() || queue.front().handle.empty() ? "" : " #" + queue.front().handle) + " on layer \"" +
              s.style.layer + "\"";
    if (!queue.empty()) queue.pop_front();
    if (ocs || type == Shape::Type::ellipse) {
      const double* n = getExtrusion()->getDirection();
      if (std::abs(n[0]) > 1e-9 || std::abs(n[1]) > 1e-9 || std::abs(std::abs(n[2]) - 1) > 1e-9)
        fail(s.where, "drawn out of the sheet's plane (extrusion " + format_decimal(n[0], 3) + ", " +
                          format_decimal(n[1], 3) + ", " + format_decimal(n[2], 3) + "): a pattern is flat");
      s.mirrored = n[2] < 0;
      s.ocs = ocs;
    }
    std::vector<Shape>& into = block_ ? block_->shapes : out.model;
    into.push_back(std::move(s));
    return into.back();
  }

  Shape* last(Shape::Type type) {
    std::vector<Shape>& in = block_ ? block_->shapes : out.model;
    return !in.empty() && in.back().type == type ? &in.back() : nullptr;
  }

  const std::string& source_;
  std::map<std::string, std::deque<EntityPlace>> places_;
  Block* block_ = nullptr;
};

}  // namespace

Collected collect(const Scan& scan, const std::string& source) {
  Collector c(scan, source);
  DL_Dxf dxf;
  std::istringstream in(scan.kept);
  dxf.in(in, &c);
  return std::move(c.out);
}

}  // namespace popcut::dxf
