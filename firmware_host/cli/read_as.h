// How a command reads a drawing: as an OA card (the default) or as a general sheet that folds rigidly (--as sheet).
#pragma once

#include <CLI/CLI.hpp>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "popcut/fold/sheet_fold.h"
#include "popcut/pattern/pattern.h"
#include "popcut/text.h"  // is_decimal_text

namespace popcut::cli {

struct ReadAs {
  std::string as = "card";
  std::vector<std::string> folds;       // --fold SELECTOR=DEGREES
  std::vector<std::string> fold_lines;  // --fold-line X1,V1,X2,V2[,under], in order
  double crease_deg = 90;               // --crease-angle
  int fixed = -1;                       // --fixed REGION
  bool crease_given = false;            // --crease-angle was on the command line
  bool sheet() const { return as == "sheet"; }
};

// Exit 2 naming the option when --fold, --crease-angle or --fixed come without --as sheet: they
// would change nothing, and silence would let a user think they did.
void check_read_as(const ReadAs& read_as);

// --as, and (when the command folds) --fold, --crease-angle and --fixed.
void add_read_as_options(CLI::App* command, ReadAs& read_as, bool folds);

// The drawing at `path` as a folding sheet; bad input (a model file, a bad --fold) is exit 2.
FoldableSheet load_cli_sheet(const std::string& path, const ReadAs& read_as, const DrawingOptions& drawing = {},
                             const SheetMapOptions& map = {});

// What a command cuts or draws: the card's pattern, or with --as sheet the sheet's own lines.
Pattern load_cli_pattern(const std::string& path, const ReadAs& read_as);

// What `submit` sends for a drawing or a webOAcard .oa card: the card's face model (popcut.faces.v1), or with --as
// sheet the sheet's lines as a pattern (popcut.pattern.v1), which popcutd cuts as it is.
std::string drawing_job_model(const std::string& path, const ReadAs& read_as);

// validate --as sheet: the hinges, pieces, creases that cannot fold, open cycles and collisions
// over `frames` steps of the motion, for people and as popcut.sheet-check.v1 JSON.
nlohmann::json sheet_check_json(const std::string& source, const FoldableSheet& sheet, const SheetMotionReport& r);
void print_sheet_check(std::ostream& out, const std::string& source, const FoldableSheet& sheet,
                       const SheetMotionReport& r);
// Exit 0 when the sheet folds as drawn without a problem, 1 when it does not.
int sheet_check_exit(const FoldableSheet& sheet, const SheetMotionReport& r);

}  // namespace popcut::cli
