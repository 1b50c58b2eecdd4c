// PDF writer through cairo: the pattern at true size (1 mm on the sheet is 1 mm on the page) for printing and cutters.
#include <cairo-pdf.h>
#include <cairo.h>

#include <ostream>

#include "popcut/error.h"
#include "popcut/io/pattern_io.h"

namespace popcut {
namespace {

constexpr double kPtPerMm = 72 / 25.4;

cairo_status_t to_stream(void* closure, const unsigned char* data, unsigned int length) {
  auto& out = *static_cast<std::ostream*>(closure);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(length));
  return out ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

// The SVG's look: cut solid black, mountain red dash-dot, valley blue dashed (mm).
void stroke_kind(cairo_t* cr, const Pattern& p, LineKind kind) {
  static const double kDashed[] = {3, 1.5};
  static const double kDashDot[] = {3, 1, 0.4, 1};
  switch (kind) {
    case LineKind::cut:
      cairo_set_source_rgb(cr, 0, 0, 0);
      cairo_set_dash(cr, nullptr, 0, 0);
      break;
    case LineKind::mountain:
      cairo_set_source_rgb(cr, 0.84, 0.15, 0.16);
      cairo_set_dash(cr, kDashDot, 4, 0);
      break;
    case LineKind::valley:
      cairo_set_source_rgb(cr, 0.12, 0.37, 0.84);
      cairo_set_dash(cr, kDashed, 2, 0);
      break;
  }
  for (const Segment& s : p.lines) {
    if (s.kind != kind) continue;
    cairo_move_to(cr, s.a.x_mm, s.a.v_mm);
    cairo_line_to(cr, s.b.x_mm, s.b.v_mm);
  }
  cairo_stroke(cr);
}

}  // namespace

void write_pattern_pdf(std::ostream& out, const Pattern& pattern) {
  const Rect& s = pattern.sheet;
  const double w = s.max.x_mm - s.min.x_mm, h = s.max.v_mm - s.min.v_mm;
  cairo_surface_t* surface = cairo_pdf_surface_create_for_stream(to_stream, &out, w * kPtPerMm, h * kPtPerMm);
  cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATOR, "popcut");
  cairo_t* cr = cairo_create(surface);
  // Millimetres, v up the back board as in the pattern (the page's y runs down).
  cairo_scale(cr, kPtPerMm, -kPtPerMm);
  cairo_translate(cr, -s.min.x_mm, -s.max.v_mm);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_width(cr, 0.1);
  cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
  cairo_rectangle(cr, s.min.x_mm, s.min.v_mm, w, h);
  cairo_stroke(cr);
  cairo_set_line_width(cr, 0.25);
  for (LineKind kind : {LineKind::valley, LineKind::mountain, LineKind::cut}) stroke_kind(cr, pattern, kind);
  cairo_show_page(cr);
  const cairo_status_t status = cairo_status(cr);
  cairo_destroy(cr);
  cairo_surface_finish(surface);
  const cairo_status_t finished = cairo_surface_status(surface);
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS || finished != CAIRO_STATUS_SUCCESS)
    throw Error(ErrorCode::io, "", "",
                std::string("the PDF was not written: ") +
                    cairo_status_to_string(status != CAIRO_STATUS_SUCCESS ? status : finished));
}

}  // namespace popcut
