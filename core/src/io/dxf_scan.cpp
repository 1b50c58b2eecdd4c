// DXF group pairs checked line by line before the DXF library sees them; what popcut reads is kept.
#include "io/dxf_scan.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <set>

#include "popcut/error.h"

namespace popcut::dxf {
namespace {

struct Pair {
  int code = 0;
  std::string value;
  std::size_t line = 0;  // of the group code
};

enum class Value { text, real, integer };

// The value type DXF gives each group code (the DXF reference's group code ranges).
Value value_type(int c) {
  const auto in = [c](int lo, int hi) { return c >= lo && c <= hi; };
  if (in(10, 59) || in(110, 149) || in(210, 239) || in(460, 469) || in(1010, 1059)) return Value::real;
  if (in(60, 99) || in(160, 179) || in(270, 299) || in(370, 389) || in(400, 409) || in(420, 429) || in(440, 459) ||
      in(1060, 1071))
    return Value::integer;
  return Value::text;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

class Reader {
 public:
  Reader(const std::string& text, const std::string& source) : text_(text), source_(source) {}

  [[noreturn]] void fail(std::size_t line, const std::string& message,
                         ErrorCode code = ErrorCode::invalid_input) const {
    throw Error(code, source_, "line " + std::to_string(line), message);
  }

  // The next pair, checked; false at the end of the text.
  bool next(Pair& p) {
    std::string code_line;
    if (!line(code_line)) return false;
    p.line = line_no_;
    const std::string c = trim(code_line);
    char* end = nullptr;
    errno = 0;
    const long code = std::strtol(c.c_str(), &end, 10);
    if (c.empty() || *end != '\0' || errno != 0 || code < -5 || code > 1071)
      fail(p.line, "expected a group code (an integer from 0 to 1071), got \"" + c.substr(0, 40) + "\"");
    p.code = static_cast<int>(code);
    if (!line(p.value)) fail(p.line, "group code " + c + " has no value: the file is truncated");
    check_value(p);
    return true;
  }

 private:
  bool line(std::string& out) {
    if (pos_ >= text_.size()) return false;
    const auto nl = text_.find('\n', pos_);
    const std::size_t end = nl == std::string::npos ? text_.size() : nl;
    out.assign(text_, pos_, end - pos_);
    if (!out.empty() && out.back() == '\r') out.pop_back();
    pos_ = end + 1;
    ++line_no_;
    return true;
  }

  void check_value(const Pair& p) const {
    const Value type = value_type(p.code);
    if (type == Value::text) return;
    const std::string v = trim(p.value);
    char* end = nullptr;
    errno = 0;
    if (type == Value::real) {
      const double d = std::strtod(v.c_str(), &end);
      if (v.empty() || *end != '\0' || !std::isfinite(d))
        fail(p.line + 1, "group code " + std::to_string(p.code) + " expects a number, got \"" + v.substr(0, 40) + "\"");
    } else {
      std::strtoll(v.c_str(), &end, 10);
      if (v.empty() || *end != '\0' || errno != 0)
        fail(p.line + 1,
             "group code " + std::to_string(p.code) + " expects an integer, got \"" + v.substr(0, 40) + "\"");
    }
  }

  const std::string& text_;
  const std::string& source_;
  std::size_t pos_ = 0;
  std::size_t line_no_ = 0;
};

const std::set<std::string>& read_types() {
  static const std::set<std::string> types = {"LINE",   "LWPOLYLINE", "POLYLINE", "ARC",
                                              "CIRCLE", "ELLIPSE",    "SPLINE",   "INSERT"};
  return types;
}

long value_int(const Pair& p) { return std::strtol(p.value.c_str(), nullptr, 10); }

// One record: a group 0 pair and the pairs up to the next group 0.
struct Record {
  std::vector<Pair> pairs;
  const std::string& type() const { return pairs.front().value; }
  std::size_t count(int code) const {
    std::size_t n = 0;
    for (const Pair& p : pairs) n += p.code == code;
    return n;
  }
  const Pair* find(int code) const {
    for (const Pair& p : pairs)
      if (p.code == code) return &p;
    return nullptr;
  }
};

class Scanner {
 public:
  Scanner(const std::string& text, const std::string& source, std::size_t max_points)
      : in_(text, source), max_points_(max_points) {}

  Scan run() {
    Record r;
    bool have = false;
    Pair p;
    for (;;) {
      const bool more = in_.next(p);
      if (!more || p.code == 0) {
        if (have && handle(r)) return std::move(out_);
        if (!more) break;
        r.pairs.assign(1, p);
        r.pairs.front().value = trim(p.value);
        have = true;
      } else if (have) {
        r.pairs.push_back(p);
      } else if (p.code != 999) {  // comments may come before the first section
        in_.fail(p.line, "expected group code 0 (the start of a section), got group code " + std::to_string(p.code));
      }
    }
    in_.fail(r.pairs.empty() ? 1 : r.pairs.back().line,
             "the file ends without \"0 EOF\": it is truncated (or not a DXF file)");
  }

 private:
  void keep(const Record& r) {
    for (const Pair& p : r.pairs) {
      // dxflib reads lines into a 1,024-byte buffer and would never get past a longer one.
      if (p.value.size() > 1000)
        in_.fail(p.line + 1,
                 "a value of " + std::to_string(p.value.size()) + " characters: DXF values are at most 1000 here");
      out_.kept += std::to_string(p.code);
      out_.kept += '\n';
      out_.kept += p.value;
      out_.kept += '\n';
    }
  }

  // Points an entity brings, so a file can be refused before any of it is flattened.
  void count_points(std::size_t n, const Record& r) {
    if ((points_ += n) > max_points_)
      in_.fail(r.pairs.front().line,
               "the drawing has more than " + std::to_string(max_points_) + " points, the documented limit",
               ErrorCode::limit);
  }

  void check_count(const Record& r, int count_code, int item_code, const char* what) {
    if (r.count(count_code) > 1)
      in_.fail(r.pairs.front().line,
               r.type() + " gives its count of " + what + " (group " + std::to_string(count_code) + ") more than once");
    const Pair* declared = r.find(count_code);
    const std::size_t have = r.count(item_code);
    const long said = declared ? value_int(*declared) : 0;
    if (said < 0 || static_cast<std::size_t>(said) != have)
      in_.fail(declared ? declared->line : r.pairs.front().line, r.type() + " says " + std::to_string(said) + " " +
                                                                     what + " (group " + std::to_string(count_code) +
                                                                     ") but has " + std::to_string(have));
    count_points(have, r);
  }

  void entity(const Record& r) {
    const std::string& type = r.type();
    if (const Pair* space = r.find(67); space && value_int(*space) == 1) {
      ++out_.paper_space;
      return;
    }
    if ((type == "VERTEX" || type == "SEQEND") && in_polyline_) {
      // A spline-fit polyline's frame (flag 16) is its control polygon, not part of the line.
      if (const Pair* flags = r.find(70); type == "VERTEX" && flags && (value_int(*flags) & 16)) return;
      if (type == "VERTEX") count_points(1, r);
      in_polyline_ = type == "VERTEX";
      keep(r);
      return;
    }
    in_polyline_ = false;
    if (!read_types().count(type)) {
      if (type != "SEQEND" && type != "ATTRIB") ++out_.skipped[type];
      return;
    }
    if (type == "LWPOLYLINE") check_count(r, 90, 10, "vertices");
    if (type == "SPLINE") {
      check_count(r, 72, 40, "knots");
      check_count(r, 73, 10, "control points");
      check_count(r, 74, 11, "fit points");
      if (r.count(41) > r.count(10))
        in_.fail(r.pairs.front().line, "SPLINE has more weights (group 41) than control points");
    }
    if (type == "LINE") count_points(2, r);
    if (const Pair* name = r.find(2); type == "INSERT" && (!name || trim(name->value).empty()))
      in_.fail(r.pairs.front().line, "an INSERT without a block name (group 2)");
    in_polyline_ = type == "POLYLINE";
    const Pair* handle = r.find(5);
    out_.entities.push_back({type, r.pairs.front().line, handle ? trim(handle->value) : ""});
    keep(r);
  }

  // True at EOF.
  bool handle(const Record& r) {
    const std::string& type = r.type();
    if (type == "EOF") {
      out_.kept += "0\nEOF\n";  // so dxflib ends the last entity even where ENDSEC is missing
      return true;
    }
    if (type == "SECTION") {
      const Pair* name = r.find(2);
      section_ = name ? trim(name->value) : "";
      if (section_ == "HEADER" || section_ == "TABLES" || section_ == "BLOCKS" || section_ == "ENTITIES") keep(r);
      if (section_ == "HEADER") header(r);
      return false;
    }
    if (type == "ENDSEC") {
      if (section_ == "HEADER" || section_ == "TABLES" || section_ == "BLOCKS" || section_ == "ENTITIES") keep(r);
      section_.clear();
      return false;
    }
    if (section_ == "HEADER") {
      return false;  // its variables are all in the SECTION record; anything else is not a header
    } else if (section_ == "TABLES") {
      if (type == "TABLE") {
        const Pair* name = r.find(2);
        table_ = name ? trim(name->value) : "";
      }
      if (table_ == "LAYER" && (type == "TABLE" || type == "LAYER" || type == "ENDTAB")) keep(r);
      if (type == "ENDTAB") table_.clear();
    } else if (section_ == "BLOCKS" && (type == "BLOCK" || type == "ENDBLK")) {
      if (const Pair* name = r.find(2); type == "BLOCK" && (!name || trim(name->value).empty()))
        in_.fail(r.pairs.front().line, "a BLOCK without a name (group 2)");
      in_polyline_ = false;
      keep(r);
    } else if (section_ == "BLOCKS" || section_ == "ENTITIES") {
      entity(r);
    } else if (section_.empty()) {
      in_.fail(r.pairs.front().line, "expected a SECTION, got \"" + type.substr(0, 40) + "\"");
    }
    return false;
  }

  // The header section is one record of 9/value pairs: $INSUNITS is a 9 followed by a 70.
  void header(const Record& r) {
    for (std::size_t i = 0; i + 1 < r.pairs.size(); ++i)
      if (r.pairs[i].code == 9 && trim(r.pairs[i].value) == "$INSUNITS" && r.pairs[i + 1].code == 70)
        out_.insunits = static_cast<int>(value_int(r.pairs[i + 1]));
  }

  Reader in_;
  std::size_t max_points_;
  Scan out_;
  std::string section_, table_;
  bool in_polyline_ = false;
  std::size_t points_ = 0;
};

}  // namespace

Scan scan(const std::string& text, const std::string& source, std::size_t max_points) {
  if (text.rfind("AutoCAD Binary DXF", 0) == 0)
    throw Error(ErrorCode::invalid_input, source, "",
                "a binary DXF file: popcut reads ASCII DXF (save as ASCII/text DXF in the CAD program)");
  return Scanner(text, source, max_points).run();
}

}  // namespace popcut::dxf
