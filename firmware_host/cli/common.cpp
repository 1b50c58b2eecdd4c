// The pieces every popcut subcommand shares: guarded bodies, exit codes, model loading, output files, JSON lines.
#include "cli/common.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <iostream>
#include <new>
#include <system_error>
#include <variant>

#include "popcut/io/files.h"
#include "popcut/io/model_io.h"
#include "popcut/pattern/card_from_sheet.h"
#include "popcut/pattern/face_pattern.h"
#include "popcut/pattern/popup_check.h"
#include "popcut/pattern/voxel_pattern.h"
#include "report_json.h"

namespace popcut::cli {

using nlohmann::json;

CliError::CliError(int exit_code, ErrorCode code, std::string source, std::string location, std::string message)
    : Error(code, std::move(source), std::move(location), std::move(message)), exit_code_(exit_code) {}

int exit_code_of(const Error& error) {
  if (const auto* cli = dynamic_cast<const CliError*>(&error)) return cli->exit_code();
  // A drawing no card folds from is a design that does not pop up, not an unreadable file.
  if (dynamic_cast<const CardConflictError*>(&error)) return kDoesNotPopUp;
  return error.code() == ErrorCode::internal ? kInternal : kBadInput;
}

int run_guarded(bool json_errors, const std::function<int()>& body) {
  try {
    return body();
  } catch (const Error& e) {
    // An error in a command-line option names the option; there is no file to blame.
    const bool option_error = e.source().empty() && e.location().rfind("--", 0) == 0;
    std::cerr << "popcut: error: " << (option_error ? e.location() + ": " + e.message() : std::string(e.what()))
              << "\n";
    if (json_errors) {
      print_json_line({{"error",
                        {{"code", to_string(e.code())},
                         {"source", e.source()},
                         {"location", e.location()},
                         {"message", e.message()}}}});
    }
    return exit_code_of(e);
  } catch (const std::bad_alloc&) {
    std::cerr << "popcut: error: out of memory\n";
    return kBadInput;
  } catch (const std::exception& e) {
    std::cerr << "popcut: internal error: " << e.what() << "\n";
    return kInternal;
  }
}

// A face model that leaves a piece cut free of the sheet is bad input (exit 2, naming the edit
// that drew it): its edits were meant to build one sheet. A voxel model's loose pieces (windows
// that float, voxel paper Fig. 8) are what validation reports.
Pattern load_cli_pattern(const std::string& model_path) {
  const AnyModel model = load_model(model_path);
  Pattern p = make_pattern(model, shown(model_path));
  if (const FaceModel* faces = std::get_if<FaceModel>(&model))
    require_attached(*faces, p, check_popup(p), shown(model_path));
  return p;
}

void write_cli_output(const std::string& path, const std::function<void(std::ostream&)>& content) {
  try {
    write_text_file(path, content);
  } catch (const Error& e) {
    throw CliError(kCannotWrite, ErrorCode::io, e.source(), "output", e.message());
  }
}

// File names from the command line may not be UTF-8, so replace.
void print_json_line(const json& j) {
  std::cout << rounded_numbers(j).dump(-1, ' ', false, json::error_handler_t::replace) << "\n";
}

std::string shown(const std::string& path) { return path == "-" ? "<stdin>" : path; }

namespace {

std::string extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return e;
}

}  // namespace

std::string require_extension(const std::string& path, std::initializer_list<const char*> allowed, const char* what,
                              const char* option) {
  const std::string ext = extension(path);
  std::string list;
  for (const char* a : allowed) {
    if (ext == a) return ext;
    list += std::string(list.empty() ? "" : " or ") + a;
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw Error(ErrorCode::invalid_input, path, option,
                std::string("is a directory: name a file in it ending ") + list);
  }
  if (ext.empty())
    throw Error(ErrorCode::invalid_input, path, option,
                std::string("no file extension to tell the ") + what + ": use " + list);
  throw Error(ErrorCode::invalid_input, path, option, std::string("unknown ") + what + " '" + ext + "': use " + list);
}

}  // namespace popcut::cli
