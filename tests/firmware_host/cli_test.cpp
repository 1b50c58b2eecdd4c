// The popcut binary end to end: subcommands, files, exit codes and messages, run as a user would.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unistd.h>

#include "popcut/io/pattern_io.h"
#include "popcut/io/voxel_json.h"
#include "popcut/pattern/popup_check.h"

namespace {
namespace fs = std::filesystem;

struct Result {
  int code;
  std::string out;
  std::string err;
};

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("popcut-cli-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string file(const std::string& name, const std::string& content) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << content;
    return p.string();
  }
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  Result run(const std::string& args, const std::string& stdin_file = "/dev/null") {
    const std::string cmd = std::string(POPCUT_CLI) + " " + args + " <" + stdin_file + " >" + (dir_ / "out").string() +
                            " 2>" + (dir_ / "err").string();
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir_ / "out"), slurp(dir_ / "err")};
  }
  fs::path dir_;
};

const char* kBox = R"({"format": "popcut.voxel.v1", "voxel_mm": 2, "heights": [[3, 3], [3, 3], [3, 3]]})";
const char* kSplit = R"({"format": "popcut.voxel.v1", "voxel_mm": 2, "heights": [[3]], "windows": [[0, 1]]})";

TEST_F(Cli, HelpEverywhere) {
  for (const char* sub : {"", "pattern ", "validate ", "repair ", "fold ", "render ", "import ", "move ", "jobs "}) {
    const Result r = run(std::string(sub) + "--help");
    EXPECT_EQ(r.code, 0) << "'" << sub << "--help' exits 0";
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << "'" << sub << "--help' prints usage: " << r.out;
  }
  EXPECT_NE(run("--help").out.find("Exit codes"), std::string::npos) << "top-level help documents exit codes";
  EXPECT_EQ(run("--version").out, std::string("popcut ") + POPCUT_VERSION + "\n")
      << "--version gives the project's version";
}

TEST_F(Cli, UsageErrorsExit2) {
  EXPECT_EQ(run("").code, 2) << "no subcommand";
  EXPECT_EQ(run("frobnicate").code, 2) << "unknown subcommand";
  EXPECT_EQ(run("validate").code, 2) << "missing MODEL";
  EXPECT_EQ(run("pattern " + file("m.json", kBox)).code, 2) << "pattern without -o";
  EXPECT_EQ(run("validate --bogus x").code, 2) << "unknown flag";
  const Result typo = run("valdate x.json");
  EXPECT_EQ(typo.code, 2) << "a misspelt command";
  EXPECT_NE(typo.err.find("unknown command 'valdate'"), std::string::npos) << "is named: " << typo.err;
  // The command table (cli/commands.cpp) builds the list of commands; scripts may match its text.
  EXPECT_EQ(
      typo.err,
      "popcut: error: unknown command 'valdate' (expected pattern, validate, repair, fold, render, import, "
      "import-pattern, "
      "plan, cut, "
      "test-cut, calibrate, submit, jobs, move, cancel, sheet, pause, continue, devices or sim-plotter)\nRun 'popcut "
      "--help' for "
      "usage.\n");
  const Result flag = run("validate --jsn x.json");
  EXPECT_EQ(flag.err.rfind("popcut: error: ", 0), 0u) << "usage errors read like every other error: " << flag.err;
  EXPECT_NE(flag.err.find("popcut validate --help"), std::string::npos) << "and point at the right help: " << flag.err;
}

TEST_F(Cli, ValidateReportsAndExitCodes) {
  Result ok = run("validate " + file("box.json", kBox));
  EXPECT_EQ(ok.code, 0) << ok.out << ok.err;
  EXPECT_NE(ok.out.find("pops up"), std::string::npos) << ok.out;

  Result bad = run("validate " + file("split.json", kSplit));
  EXPECT_EQ(bad.code, 1) << "a card that does not pop up exits 1: " << bad.out;
  EXPECT_NE(bad.out.find("would not stand: face"), std::string::npos) << "names the failing faces: " << bad.out;
  EXPECT_NE(bad.out.find("not reached from the floor"), std::string::npos) << "says which walk misses it: " << bad.out;

  Result js = run("validate --json " + file("split2.json", kSplit));
  EXPECT_EQ(js.code, 1) << js.err;
  const auto j = nlohmann::json::parse(js.out);
  EXPECT_EQ(j["format"], "popcut.validation.v1") << js.out;
  EXPECT_FALSE(j["pops_up"].get<bool>()) << js.out;
  EXPECT_EQ(j["not_standing"].size(), 2u) << "both halves of the split front face: " << js.out;

  Result piped = run("validate -", file("stdin.json", kBox));
  EXPECT_EQ(piped.code, 0) << "a model on standard input: " << piped.err;
  Result piped_bad = run("validate -", file("stdin-bad.json", "{"));
  EXPECT_EQ(piped_bad.err.rfind("popcut: error: <stdin>: line 1", 0), 0u)
      << "standard input is named: " << piped_bad.err;
}

TEST_F(Cli, BadInputExit2WithFileAndPosition) {
  Result r = run(
      "validate " +
      file("broken.json", "{\"format\": \"popcut.voxel.v1\",\n  \"voxel_mm\": 2,\n  \"heights\": [[3, 3], [2, 4]]}"));
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("broken.json: heights[1][1]"), std::string::npos) << "file and field: " << r.err;
  Result m = run("validate " +
                 file("trunc.json", "{\"format\": \"popcut.voxel.v1\",\n  \"voxel_mm\": 2,\n  \"heights\": [[3, "));
  EXPECT_EQ(m.code, 2) << m.err;
  EXPECT_NE(m.err.find("trunc.json: line 3"), std::string::npos) << "file and line: " << m.err;
  Result missing = run("validate " + (dir_ / "nope.json").string());
  EXPECT_EQ(missing.code, 2) << missing.err;
  EXPECT_NE(missing.err.find("no such file"), std::string::npos) << missing.err;
  Result js = run("validate --json " + file("b2.json", "[]"));
  EXPECT_EQ(js.code, 2) << js.err;
  EXPECT_EQ(nlohmann::json::parse(js.out)["error"]["code"], "invalid_input") << "JSON error object: " << js.out;
}

TEST_F(Cli, PatternWritesSvgAndJson) {
  const std::string model = file("box.json", kBox);
  const fs::path svg = dir_ / "p.svg", js = dir_ / "p.json";
  ASSERT_EQ(run("pattern " + model + " -o " + svg.string()).code, 0);
  EXPECT_EQ(slurp(svg).rfind("<?xml", 0), 0u) << "an SVG document";
  ASSERT_EQ(run("pattern " + model + " -o " + js.string()).code, 0);
  const popcut::Pattern p = popcut::parse_pattern(slurp(js), js.string());
  EXPECT_TRUE(popcut::check_popup(p).pops_up()) << "the written pattern carries enough to re-check it";
  Result summary = run("pattern " + model + " -o " + (dir_ / "q.svg").string() + " --json");
  EXPECT_EQ(nlohmann::json::parse(summary.out)["output"], (dir_ / "q.svg").string()) << summary.out;
  EXPECT_EQ(run("pattern " + model + " -o " + (dir_ / "p.txt").string()).code, 2) << "unknown extension";
  EXPECT_EQ(run("pattern " + model + " --shade -o " + (dir_ / "s.json").string()).code, 2) << "--shade is for SVG only";
  const Result said = run("pattern " + model + " -o " + svg.string());
  EXPECT_NE(said.err.find("wrote " + svg.string()), std::string::npos) << "pattern says what it wrote: " << said.err;
  EXPECT_FALSE(fs::exists(dir_ / "p.txt")) << "nothing written on error";
  Result nodir = run("pattern " + model + " -o " + (dir_ / "missing" / "p.svg").string());
  EXPECT_EQ(nodir.code, 3) << "an unwritable output exits 3: " << nodir.err;
  Result warn = run("pattern " + file("split.json", kSplit) + " -o " + (dir_ / "s.svg").string());
  EXPECT_EQ(warn.code, 0) << "the pattern is still written";
  EXPECT_NE(warn.err.find("will not pop up"), std::string::npos) << "with a warning: " << warn.err;
}

TEST_F(Cli, RepairMakesAValidModel) {
  const std::string model = file("tower.json", R"({"format": "popcut.voxel.v1", "voxel_mm": 2,
    "heights": [[1, 4, 2], [2, 2, 3], [0, 0, 1]]})");
  EXPECT_EQ(run("validate " + model).code, 2) << "the input breaks the staircase";
  const fs::path fixed = dir_ / "fixed.json";
  Result r = run("repair " + model + " -o " + fixed.string() + " --windows --json");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_GT(j["cells_filled"].get<int>(), 0) << r.out;
  EXPECT_TRUE(j["pops_up"].get<bool>()) << "repair --windows keeps only windows that pop up: " << r.out;
  EXPECT_EQ(run("validate " + fixed.string()).code, 0) << "the repaired file validates";
}

TEST_F(Cli, PaperFailureFixtures) {
  const fs::path data = fs::path(POPCUT_SOURCE_DIR) / "tests" / "data";
  Result floating = run("validate " + (data / "fig8a_floating.json").string());
  EXPECT_EQ(floating.code, 1) << floating.out;
  EXPECT_NE(floating.out.find("cut free, would fall out: 2 faces"), std::string::npos) << floating.out;
  Result split = run("validate " + (data / "fig8b_split.json").string());
  EXPECT_EQ(split.code, 1) << split.out;
  EXPECT_NE(split.out.find("not reached from the back board"), std::string::npos) << "lower part: " << split.out;
  EXPECT_NE(split.out.find("not reached from the floor"), std::string::npos) << "upper part: " << split.out;
}

TEST_F(Cli, ShippedExamplesValidate) {
  for (const char* kind : {"voxel", "faces", "meshes"}) {
    int seen = 0;
    for (const auto& e : fs::directory_iterator(fs::path(POPCUT_SOURCE_DIR) / "examples" / kind)) {
      if (e.path().extension() != ".json") continue;
      ++seen;
      Result r = run("validate " + e.path().string());
      EXPECT_EQ(r.code, 0) << e.path() << " must pop up: " << r.out << r.err;
      EXPECT_EQ(run("pattern " + e.path().string() + " -o " + (dir_ / "x.svg").string()).code, 0) << e.path();
    }
    EXPECT_GE(seen, 3) << "examples/" << kind << " holds at least three models";
  }
}

TEST_F(Cli, ImportMeshToCardAndPattern) {
  const fs::path meshes = fs::path(POPCUT_SOURCE_DIR) / "examples" / "meshes";
  const fs::path card = dir_ / "house.json", svg = dir_ / "house.svg";
  Result r = run("import " + (meshes / "house.obj").string() + " -o " + card.string() + " --resolution 30 --pattern " +
                 svg.string() + " --json");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_TRUE(j["pops_up"].get<bool>()) << r.out;
  EXPECT_EQ(j["grid"]["width"].get<int>(), 30) << "--resolution sets the voxels across";
  EXPECT_EQ(j["mesh"]["triangles"].get<int>(), 28) << r.out;
  for (const char* step : {"read", "sampling", "morphology", "filling", "windows", "thin_tops"}) {
    EXPECT_TRUE(j["timings_ms"].contains(step)) << "the timing of " << step << " is reported";
  }
  EXPECT_EQ(run("validate " + card.string()).code, 0) << "the card validates";
  EXPECT_NE(slurp(svg).find("<svg"), std::string::npos) << "--pattern writes the SVG";
  // -y as the value of --front, Y-up axes, voxel size instead of width.
  r = run("import " + (meshes / "tower.ply").string() + " -o " + card.string() +
          " --up +z --front -y --voxel-mm 2 --resolution 20");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("voxels of 2 mm"), std::string::npos) << r.out;
}

TEST_F(Cli, ShippedMeshCardsAreWhatImportMakes) {
  // examples/meshes/NAME.json was made by: popcut import NAME.* -o NAME.json --resolution 40 --thin-tops 1
  const fs::path meshes = fs::path(POPCUT_SOURCE_DIR) / "examples" / "meshes";
  for (const char* mesh : {"house.obj", "arch.off", "tower.ply"}) {
    const fs::path card = dir_ / "card.json";
    Result r = run("import " + (meshes / mesh).string() + " -o " + card.string() + " --resolution 40 --thin-tops 1");
    ASSERT_EQ(r.code, 0) << mesh << ": " << r.err;
    EXPECT_EQ(popcut::parse_voxel_model(slurp(card), "made"),
              popcut::parse_voxel_model(slurp(meshes / (fs::path(mesh).stem().string() + ".json")), "shipped"))
        << mesh << ": the shipped card is out of date";
  }
}

TEST_F(Cli, ImportFacesFollowTheSilhouette) {
  const fs::path meshes = fs::path(POPCUT_SOURCE_DIR) / "examples" / "meshes";
  const fs::path card = dir_ / "house-faces.json";
  Result r = run("import " + (meshes / "house.obj").string() + " -o " + card.string() +
                 " --resolution 40 --thin-tops 2 --faces --json");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_GT(j["faces"]["outlines_redrawn"].get<int>(), 0) << r.out;
  EXPECT_LT(j["faces"]["face_mean_mm"].get<double>(), j["faces"]["voxel_mean_mm"].get<double>()) << r.out;
  EXPECT_NE(slurp(card).find("popcut.faces.v1"), std::string::npos) << "--faces writes a face model";
  EXPECT_EQ(run("validate " + card.string()).code, 0) << "which validates";
}

TEST_F(Cli, ImportErrorsNameFileAndOption) {
  const std::string obj = file("house.obj", "v 0 0 0\nv 1 0 0\nv 0 1 1\nf 1 2 3\n");
  Result r = run("import " + obj + " -o " + (dir_ / "x.json").string() + " --front +z");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--front: must be perpendicular to --up"), std::string::npos) << r.err;
  r = run("import " + obj + " -o " + (dir_ / "x.json").string() + " --up sideways");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--up: 'sideways' is not an axis"), std::string::npos) << r.err;
  // Every option: the mesh and the option named (no "<input>"), the allowed values, a short number.
  const std::vector<std::pair<std::string, std::string>> numbers = {
      {"--up +q", "house.obj: --up: '+q' is not an axis: use +x, -x, +y, -y, +z or -z"},
      {"--depth-method fast", "house.obj: --depth-method: 'fast' is not a method: use zbuffer or raycast"},
      {"--resolution 1e10", "house.obj: --resolution: '1e10' is not a whole number: expected 1 to 2048 voxels across"},
      {"--resolution 99999999999",
       "house.obj: --resolution: '99999999999' is out of range: expected 1 to 2048 voxels across"},
      {"--smooth 3.5", "house.obj: --smooth: '3.5' is not a whole number: expected an odd side, 1 to 15"},
      {"--thin-tops -99999999999",
       "house.obj: --thin-tops: '-99999999999' is out of range: expected 0 (off) to 4096 voxels"},
      {"--width-mm 1e308", "--width-mm: gives voxels of 1.25e+306 mm; they must be 0.01 to 1000 mm"},
      {"--voxel-mm nan", "--voxel-mm: the voxel size must be a positive number of mm, not nan"},
      {"--width-mm -5", "--width-mm: the card width must be a positive number of mm, not -5"},
      {"--keep-depth 1e308", "--keep-depth: must be a fraction above 0 and at most 1, not 1e+308"},
  };
  for (const auto& [flags, message] : numbers) {
    r = run("import " + obj + " -o " + (dir_ / "x.json").string() + " " + flags);
    EXPECT_EQ(r.code, 2) << flags << ": bad input";
    EXPECT_NE(r.err.find(message), std::string::npos) << flags << ": expected '" << message << "', got " << r.err;
    EXPECT_EQ(r.err.find("<input>"), std::string::npos) << flags << ": the mesh is named, not <input>: " << r.err;
    EXPECT_LT(r.err.size(), 200u) << flags << ": the message stays short: " << r.err;
  }
  r = run("import " + file("bad.obj", "v 0 0 0\nv nan 1 0\nv 0 0 1\nf 1 2 3\n") + " -o " + (dir_ / "x.json").string() +
          " --json");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("bad.obj: line 2: 'nan' is not a finite number"), std::string::npos) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["error"]["code"], "invalid_input") << r.out;
  r = run("import " + file("empty.stl", "") + " -o " + (dir_ / "x.json").string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("the file is empty"), std::string::npos) << r.err;
  r = run("import " + obj + " -o " + (dir_ / "x.svg").string());
  EXPECT_EQ(r.code, 2) << "the model goes to JSON";
  r = run("import " + obj + " -o /nonexistent/dir/x.json");
  EXPECT_EQ(r.code, 3) << "an unwritable output is exit 3: " << r.err;
}

TEST_F(Cli, FoldWritesObjAndGltf) {
  const std::string model = file("box.json", kBox);
  Result obj = run("fold " + model + " --angle 45 -o " + (dir_ / "card.obj").string());
  EXPECT_EQ(obj.code, 0) << obj.err;
  EXPECT_TRUE(fs::exists(dir_ / "card.mtl")) << "the OBJ's materials are written beside it";
  EXPECT_NE(slurp(dir_ / "card.obj").find("mtllib card.mtl"), std::string::npos) << "and named relative to it";
  Result gltf = run("fold " + model + " -o " + (dir_ / "card.gltf").string());
  EXPECT_EQ(gltf.code, 0) << gltf.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(dir_ / "card.gltf"))["asset"]["version"], "2.0") << "a glTF 2.0 document";
  EXPECT_EQ(run("fold " + model + " --angle 181 -o " + (dir_ / "c.gltf").string()).code, 2) << "angle out of range";
  EXPECT_EQ(run("fold " + model + " --angle abc -o " + (dir_ / "c.gltf").string()).code, 2) << "angle not a number";
  EXPECT_EQ(run("fold " + model + " -o " + (dir_ / "c.stl").string()).code, 2) << "unknown 3D format";
  const Result into_dir = run("fold " + model + " -o " + dir_.string());
  EXPECT_EQ(into_dir.code, 2) << "a directory as -o: " << into_dir.err;
  EXPECT_NE(into_dir.err.find("is a directory"), std::string::npos)
      << "the message says it is a directory: " << into_dir.err;
  const Result bare = run("fold " + model + " -o " + (dir_ / "card").string());
  EXPECT_NE(bare.err.find("no file extension"), std::string::npos)
      << "the message says the extension is missing: " << bare.err;
}

TEST_F(Cli, RenderPicturesAndFrames) {
  const std::string model = file("box.json", kBox);
  Result svg = run("render " + model + " --angle 70 -o " + (dir_ / "card.svg").string());
  ASSERT_EQ(svg.code, 0) << svg.err;
  EXPECT_NE(slurp(dir_ / "card.svg").find("<polygon"), std::string::npos) << "an SVG of shaded triangles";
  Result png = run("render " + model + " -o " + (dir_ / "card.png").string() + " --width 120");
  ASSERT_EQ(png.code, 0) << png.err;
  EXPECT_EQ(slurp(dir_ / "card.png").substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << "a PNG file";
  Result anim = run("render " + model + " --frames 4 -o " + (dir_ / "open.svg").string());
  ASSERT_EQ(anim.code, 0) << anim.err;
  for (const char* f : {"open-000.svg", "open-001.svg", "open-002.svg", "open-003.svg"}) {
    EXPECT_TRUE(fs::exists(dir_ / f)) << "frame " << f;
  }
  EXPECT_FALSE(fs::exists(dir_ / "open-004.svg")) << "exactly four frames";
  EXPECT_NE(slurp(dir_ / "open-000.svg").substr(0, 300).find("viewBox"), std::string::npos);
  // Every frame shares one view box, so the animation holds still.
  const auto box = [&](const char* f) {
    const std::string t = slurp(dir_ / f);
    return t.substr(t.find("viewBox"), 40);
  };
  EXPECT_EQ(box("open-000.svg"), box("open-003.svg")) << "frames share their view";
  EXPECT_EQ(run("render " + model + " --frames 0 -o " + (dir_ / "x.svg").string()).code, 2) << "frames out of range";
  EXPECT_EQ(run("render " + model + " -o " + (dir_ / "x.gif").string()).code, 2) << "unknown picture format";
  EXPECT_EQ(run("render " + model + " -o " + (dir_ / "nodir" / "x.png").string()).code, 3) << "unwritable PNG";
  // A full disk: the PNG writer must notice the short write, not print "wrote".
  fs::create_symlink("/dev/full", dir_ / "full.png");
  const Result full = run("render " + model + " -o " + (dir_ / "full.png").string());
  EXPECT_EQ(full.code, 3) << "a PNG that did not fit is a write failure: " << full.err;
  EXPECT_EQ(full.err.find("wrote"), std::string::npos) << "no success message after a failed write: " << full.err;
  EXPECT_TRUE(fs::is_character_file("/dev/full"))
      << "a device behind a link is written in place, never replaced by a file";
  EXPECT_EQ(anim.err.find("frames"), anim.err.rfind("frames"))
      << "no \\r frame counter when stderr is a file: " << anim.err;
}

TEST_F(Cli, CutFaultFlagsRefuseNotANumber) {
  const std::string model = std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/box.json";
  // CLI11's Range lets NaN through; a NaN slowdown once spun the simulator forever.
  for (const char* flags :
       {"--sim-slowdown nan", "--sim-slowdown inf", "--sim-drop-after -1", "--sim-stop-after nan"}) {
    const Result r = run("cut " + model + " --device sim --out " + (dir_ / "o").string() + " " + flags);
    EXPECT_EQ(r.code, 2) << flags << ": " << r.err;
    EXPECT_LT(r.err.size(), 300u) << flags << ": a short message, not a 300-digit limit: " << r.err;
  }
}

TEST_F(Cli, ResumedCutReportsThisRun) {
  const std::string model = std::string(POPCUT_SOURCE_DIR) + "/examples/voxel/townhouse.json";
  const Result r =
      run("cut " + model + " --device sim --out " + (dir_ / "r").string() + " --resume-from 34 --no-progress");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto report = nlohmann::json::parse(slurp(dir_ / "r" / "report.json"));
  EXPECT_EQ(report["this_run"]["first_stroke"], 34) << report.dump();
  EXPECT_NEAR(report["this_run"]["cut_mm"].get<double>(), report["sim"]["cut_mm"].get<double>(), 1.0)
      << "this run's cut length is what the simulator cut from stroke 34 on";
  EXPECT_LT(report["this_run"]["cut_mm"].get<double>(), report["cut_mm"].get<double>()) << "less than the whole job";
  EXPECT_NE(r.err.find("strokes 34 to"), std::string::npos) << "the summary names the strokes of this run: " << r.err;
}

TEST_F(Cli, OutputThroughASymlinkUpdatesItsTarget) {
  const std::string model = file("box.json", kBox);
  const std::string target = file("target.svg", "old");
  fs::create_symlink("target.svg", dir_ / "link.svg");
  const Result r = run("pattern " + model + " -o " + (dir_ / "link.svg").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir_ / "link.svg"))) << "the link stays a link";
  EXPECT_NE(slurp(target).find("<svg"), std::string::npos) << "the pattern went to the link's target";
}

TEST_F(Cli, OptionErrorsNameTheOption) {
  const std::string model = file("box.json", kBox);
  const Result r = run("fold " + model + " --angle 200 -o " + (dir_ / "f.obj").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_EQ(r.err.find("<input>"), std::string::npos) << "an option error is not blamed on '<input>': " << r.err;
  EXPECT_NE(r.err.find("--angle"), std::string::npos) << "names the option: " << r.err;
  const Result p = run("import " + std::string(POPCUT_SOURCE_DIR) + "/examples/meshes/house.obj -o " +
                       (dir_ / "c.json").string() + " --pattern " + (dir_ / "p.png").string());
  EXPECT_EQ(p.code, 2) << p.err;
  EXPECT_NE(p.err.find("--pattern"), std::string::npos) << "the pattern's own option is blamed, not -o: " << p.err;
}

// One range for every opening angle: render used to clamp any angle to a picture of 179°.
TEST_F(Cli, EveryCommandRefusesAnAngleOutsideZeroTo180NamingTheFlag) {
  const std::string model = file("box.json", kBox);
  const std::vector<std::string> refused = {
      "render " + model + " --angle 1e9 -o " + (dir_ / "a.png").string(),
      "render " + model + " --frames 5 --angle 300 -o " + (dir_ / "b.svg").string(),
      "render " + model + " --angle -1 -o " + (dir_ / "c.svg").string(),
      "fold " + model + " --angle 500 -o " + (dir_ / "e.obj").string(),
      "fold " + model + " --angle -0.5 -o " + (dir_ / "f.gltf").string(),
      // The flag is named before the model is read.
      "render " + (dir_ / "missing.json").string() + " --angle 181 -o " + (dir_ / "g.svg").string(),
  };
  for (const std::string& args : refused) {
    const Result r = run(args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find("--angle: the fold angle must be from 0 (flat) to 180 (closed) degrees"), std::string::npos)
        << args << ": names the flag and the range: " << r.err;
    EXPECT_EQ(r.err.find("wrote"), std::string::npos) << args << ": nothing written: " << r.err;
  }
  // A number written otherwise than in decimal is refused as such, not read as hex.
  for (const char* angle : {"0x10", "ninety", "1,5", "nan", "inf"}) {
    const Result r = run("render " + model + " --angle " + angle + " -o " + (dir_ / "h.svg").string());
    EXPECT_EQ(r.code, 2) << angle << ": " << r.err;
    EXPECT_NE(r.err.find("--angle"), std::string::npos) << angle << ": names the flag: " << r.err;
    EXPECT_NE(r.err.find("is not a number of degrees"), std::string::npos)
        << angle << ": says what it takes: " << r.err;
  }
  const Result minus_zero = run("fold " + model + " --angle -0 -o " + (dir_ / "z.obj").string());
  EXPECT_EQ(minus_zero.code, 0) << minus_zero.err;
  EXPECT_NE(minus_zero.err.find("folded to 0°"), std::string::npos) << "-0 is 0: " << minus_zero.err;
  for (const char* angle : {"0", "180", "179.5"}) {
    const Result r = run("render " + model + " --frames 2 --angle " + angle + " -o " + (dir_ / "ok.svg").string());
    EXPECT_EQ(r.code, 0) << "--angle " << angle << " is in range: " << r.err;
  }
}

// A malformed device string is what is wrong, whatever else is missing.
TEST_F(Cli, CutNamesABadDeviceStringBeforeAMissingProfile) {
  const std::string model = file("box.json", kBox);
  for (const char* device : {"foo", "usb:0b4:110a", "serial:"}) {
    const Result r = run("cut " + model + " --device " + device + " --out " + (dir_ / "cut").string());
    EXPECT_EQ(r.code, 2) << device << ": " << r.err;
    EXPECT_NE(r.err.find("--device"), std::string::npos) << device << ": " << r.err;
    EXPECT_NE(r.err.find(std::string("(in device '") + device + "')"), std::string::npos)
        << device << ": says what is wrong with it: " << r.err;
    EXPECT_EQ(r.err.find("needs --profile"), std::string::npos)
        << device << ": not the missing profile first: " << r.err;
  }
  const Result good =
      run("cut " + model + " --device file:" + (dir_ / "x.hpgl").string() + " --out " + (dir_ / "cut").string());
  EXPECT_EQ(good.code, 2) << good.err;
  EXPECT_NE(good.err.find("needs --profile"), std::string::npos)
      << "a well-formed device still needs its profile: " << good.err;
}

// The models shown in docs/formats.md are the first a user copies: they must be valid cards.
TEST_F(Cli, FormatDocExamplesPopUp) {
  const std::string doc = slurp(fs::path(POPCUT_SOURCE_DIR) / "docs" / "formats.md");
  int checked = 0;
  for (std::size_t at = doc.find("```json\n"); at != std::string::npos; at = doc.find("```json\n", at + 1)) {
    const std::size_t start = at + 8, end = doc.find("```", start);
    const std::string block = doc.substr(start, end - start);
    if (block.find("\"popcut.voxel.v1\"") == std::string::npos &&
        block.find("\"popcut.faces.v1\"") == std::string::npos)
      continue;
    const std::string path = file("doc" + std::to_string(checked++) + ".json", block);
    const Result r = run("validate " + path);
    EXPECT_EQ(r.code, 0) << "docs/formats.md example:\n" << block << "\n" << r.out << r.err;
  }
  EXPECT_GE(checked, 2) << "the voxel and the face model examples were found";
}

TEST_F(Cli, FaceModels) {
  const std::string box =
      file("box-faces.json", R"({"format": "popcut.faces.v1", "sheet": {"width": 60, "back": 50, "floor": 50},
    "edits": [{"op": "add_vface", "t": 20, "outline": [[10, 0], [50, 0], [50, 30], [10, 30]]},
              {"op": "add_hface", "t": 30, "outline": [[10, 0], [50, 0], [50, 20], [10, 20]]}]})");
  Result ok = run("validate --json " + box);
  EXPECT_EQ(ok.code, 0) << ok.out << ok.err;
  EXPECT_TRUE(nlohmann::json::parse(ok.out)["pops_up"].get<bool>()) << ok.out;
  const std::string bowtie =
      file("bowtie.json", R"({"format": "popcut.faces.v1", "sheet": {"width": 60, "back": 50, "floor": 50},
    "edits": [{"op": "add_vface", "t": 20, "outline": [[10, 0], [50, 0], [50, 30], [10, 30]]},
              {"op": "add_vface", "t": 5, "outline": [[0, 0], [10, 10], [10, 0], [0, 10]]}]})");
  Result bad = run("validate " + bowtie);
  EXPECT_EQ(bad.code, 2) << "a self-intersecting outline is bad input: " << bad.err;
  EXPECT_NE(bad.err.find("bowtie.json: edits[1].outline: crosses"), std::string::npos) << "names the edit: " << bad.err;
  Result repair = run("repair " + box + " -o " + (dir_ / "r.json").string());
  EXPECT_EQ(repair.code, 2) << "repair is for voxel models";
  EXPECT_NE(repair.err.find("expected \"popcut.voxel.v1\", got \"popcut.faces.v1\""), std::string::npos) << repair.err;
}

TEST_F(Cli, FaceModelWithAPieceCutFreeIsBadInput) {
  // A wall at y = 5 that reaches neither the floor nor a roof: cut on every side, it would fall out.
  const std::string floating =
      file("floating.json", R"({"format": "popcut.faces.v1", "sheet": {"width": 60, "back": 50, "floor": 50},
    "edits": [{"op": "add_vface", "t": 20, "outline": [[10, 0], [50, 0], [50, 30], [10, 30]]},
              {"op": "add_vface", "t": 5, "outline": [[20, 10], [30, 10], [30, 25], [20, 25]]}]})");
  for (const std::string command : {"validate", "pattern", "render"}) {
    const std::string out =
        command == "validate" ? "" : " -o " + (dir_ / (command == "render" ? "x.svg" : "x.json")).string();
    const Result r = run(command + " " + floating + out);
    EXPECT_EQ(r.code, 2) << command << ": " << r.err;
    EXPECT_NE(r.err.find("floating.json: edits[1]: leaves a piece cut free of the sheet (1 face, x 20 to 30 mm, v 5 to "
                         "20 mm, 150 mm²)"),
              std::string::npos)
        << command << " names the edit that drew the loose face and where it is: " << r.err;
  }
  // Given as final faces, the same piece is named by its face index.
  const std::string given =
      file("given.json", R"({"format": "popcut.faces.v1", "sheet": {"width": 20, "back": 10, "floor": 10},
    "faces": [{"kind": "V", "t": 0, "outer": [[0, 0], [20, 0], [20, 10], [0, 10]]},
              {"kind": "H", "t": 0, "outer": [[0, -10], [20, -10], [20, 0], [0, 0]], "holes": [[[5, -8], [5, -2], [15, -2], [15, -8]]]},
              {"kind": "V", "t": 3, "outer": [[5, -8], [15, -8], [15, -2], [5, -2]]}]})");
  const Result r = run("validate " + given);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("given.json: faces[2]: leaves a piece cut free"), std::string::npos) << r.err;
}

}  // namespace

// ---- plan and cut ----
namespace {

std::string profile(const std::string& name) { return std::string(POPCUT_SOURCE_DIR) + "/configs/devices/" + name; }
std::string example(const std::string& name) { return std::string(POPCUT_SOURCE_DIR) + "/examples/" + name; }

TEST_F(Cli, PlanAndCutHaveHelp) {
  for (const char* sub : {"plan --help", "cut --help"}) {
    const Result r = run(sub);
    EXPECT_EQ(r.code, 0) << sub;
    EXPECT_NE(r.out.find("--profile"), std::string::npos) << sub << " documents --profile: " << r.out;
  }
}

TEST_F(Cli, PlanWritesHpglAndAReport) {
  const fs::path job = dir_ / "job.hpgl", rep = dir_ / "plan.json";
  const Result r = run("plan " + example("voxel/townhouse.json") + " --profile " + profile("generic-hpgl.toml") +
                       " -o " + job.string() + " --report " + rep.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(job).rfind("IN;SP1;", 0), 0u)
      << "the job starts with the profile's init: " << slurp(job).substr(0, 40);
  const auto j = nlohmann::json::parse(slurp(rep));
  for (const char* k : {"strokes", "pen_lifts", "pen_lift_bound", "cut_mm", "travel_mm", "est_time_s"}) {
    EXPECT_TRUE(j.contains(k)) << "report has " << k << ": " << j.dump();
    for (const char* kind : {"valley", "mountain", "cut", "outline"}) {
      EXPECT_TRUE(j["kinds"][kind].contains(k)) << kind << " has " << k;
    }
  }
  EXPECT_EQ(j["strokes"], j["pen_lift_bound"]) << "no turn limit in this profile: strokes at the Euler bound";
  EXPECT_GT(j["cut_mm"].get<double>(), 0);
  EXPECT_EQ(j["language"], "hpgl");
  EXPECT_EQ(j["job_bytes"].get<std::size_t>(), slurp(job).size());
  EXPECT_EQ(j["hpgl_bytes"], j["job_bytes"]) << "the older name stays for HP-GL jobs";
  EXPECT_NE(r.err.find("wrote " + job.string()), std::string::npos) << r.err;
}

TEST_F(Cli, PlanRejectsBadProfilesAndFlagsWithExit2) {
  const std::string model = file("box.json", kBox);
  const std::string bad = file("bad.toml", "[device]\nname = \"x\"\n[tool.cut]\nforce_g = 9000\n");
  const Result r = run("plan " + model + " --profile " + bad + " -o " + (dir_ / "j.hpgl").string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("bad.toml: [tool.cut] force_g: 9000 is out of range"), std::string::npos)
      << "file, section and key: " << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "j.hpgl")) << "nothing written on error";
  const Result js = run("plan --json " + model + " --profile " + bad + " -o " + (dir_ / "j.hpgl").string());
  EXPECT_EQ(nlohmann::json::parse(js.out)["error"]["location"], "[tool.cut] force_g") << js.out;
  EXPECT_EQ(run("plan " + model + " -o " + (dir_ / "j.hpgl").string()).code, 2) << "--profile is required";
  const Result piped = run("plan " + model + " --profile " + profile("sim.toml") + " -o -");
  EXPECT_EQ(piped.code, 0) << piped.err;
  EXPECT_EQ(piped.out.rfind("IN;", 0), 0u) << "-o - writes the job to standard output: " << piped.out.substr(0, 40);
  EXPECT_EQ(run("plan --json " + model + " --profile " + profile("sim.toml") + " -o -").code, 2)
      << "job and report both on stdout";
  EXPECT_EQ(run("plan " + model + " --profile " + (dir_ / "none.toml").string() + " -o x.hpgl").code, 2)
      << "missing profile";
  EXPECT_EQ(run("cut " + model + " --out " + dir_.string() + " --device serial:/dev/ttyS0").code, 2)
      << "unsupported device";
  EXPECT_EQ(run("cut " + model + " --out " + dir_.string() + " --sim-slowdown 0").code, 2) << "slowdown below 1";
  const Result empty =
      run("cut " + model + " --out " + dir_.string() + " --profile " + profile("generic-hpgl.toml") + " --device ''");
  EXPECT_EQ(empty.code, 2) << "an empty --device is not the profile's default: " << empty.err;
  EXPECT_NE(empty.err.find("--device"), std::string::npos) << empty.err;
  const std::string tiny = file("tiny.toml", "[device]\nname = \"tiny\"\narea_max_x_mm = 5\narea_max_y_mm = 5\n");
  const Result small = run("plan " + model + " --profile " + tiny + " -o " + (dir_ / "t.hpgl").string());
  EXPECT_EQ(small.code, 2) << "a sheet larger than the device is refused";
  EXPECT_NE(small.err.find("does not fit"), std::string::npos) << small.err;
}

// A profile with no handshake (generic HP-GL: flow_control "none") is paced by time on the
// simulator too: a device within pace_margin_percent of the plan cuts the job; one three times as slow
// loses bytes, which is the device's fault (exit 3, naming the margin), not popcut's (exit 4).
TEST_F(Cli, TimePacingOnTheSimulatorKeepsUpOrNamesTheMargin) {
  const std::string base =
      "cut " + example("voxel/castle.json") + " --profile " + profile("generic-hpgl.toml") + " --device sim --out ";
  const Result ok = run(base + (dir_ / "ok").string() + " --sim-slowdown 1.2");
  ASSERT_EQ(ok.code, 0) << ok.err;
  const auto j = nlohmann::json::parse(slurp(dir_ / "ok" / "report.json"));
  EXPECT_EQ(j["sim"]["overflow_bytes"], 0) << j.dump();
  EXPECT_TRUE(j["sim"]["strokes_match_plan"].get<bool>());
  const Result slow = run(base + (dir_ / "slow").string() + " --sim-slowdown 3");
  EXPECT_EQ(slow.code, 3) << slow.err;
  EXPECT_NE(slow.err.find("a pace margin of 25 % ([transport] pace_margin_percent in " + profile("generic-hpgl.toml")),
            std::string::npos)
      << slow.err;
  const auto slow_report = nlohmann::json::parse(slurp(dir_ / "slow" / "report.json"));
  EXPECT_GT(slow_report["sim"]["overflow_bytes"].get<int>(), 0);
  EXPECT_FALSE(slow_report["sent"]["complete"].get<bool>())
      << "a script reading `sent` sees the job did not get through";
}

TEST_F(Cli, CutOnTheSimulatorWritesJobSvgAndReport) {
  const fs::path out = dir_ / "cut";
  const Result r = run("cut " + example("voxel/townhouse.json") + " --device sim --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out / "job.hpgl"));
  EXPECT_NE(slurp(out / "cut.svg").find("<polyline"), std::string::npos) << "the simulator drew what it cut";
  const auto j = nlohmann::json::parse(slurp(out / "report.json"));
  EXPECT_EQ(j["format"], "popcut.cut.v1");
  EXPECT_TRUE(j["sim"]["strokes_match_plan"].get<bool>()) << j.dump();
  EXPECT_EQ(j["sim"]["strokes"], j["strokes"]) << "recovered as many strokes as planned";
  EXPECT_NEAR(j["sim"]["cut_mm"].get<double>(), j["cut_mm"].get<double>(), 1.0) << "knife-down length agrees";
  EXPECT_GT(j["sim"]["motion_time_s"].get<double>(), 0);
  EXPECT_EQ(r.err.find("\r"), std::string::npos) << "no progress bar when stderr is not a terminal";
}

TEST_F(Cli, CutReportsADroppedConnectionWithExit3) {
  const fs::path out = dir_ / "cut";
  const Result r =
      run("cut " + example("voxel/townhouse.json") + " --device sim --sim-drop-after 300 --out " + out.string());
  EXPECT_EQ(r.code, 3) << r.err;
  const auto j = nlohmann::json::parse(slurp(out / "report.json"));
  // 300 bytes reached the device: the job's, and 3 for each ESC.O status query.
  EXPECT_EQ(j["sent"]["bytes"].get<std::size_t>() + 3 * j["sent"]["status_queries"].get<std::size_t>(), 300u)
      << j.dump();
  EXPECT_NE(r.err.find(std::to_string(j["sent"]["bytes"].get<std::size_t>()) + " of"), std::string::npos)
      << "says how far it got: " << r.err;
  // The cutter goes on cutting what it holds; every stroke claimed received was cut, so resuming
  // after it skips nothing.
  EXPECT_GE(j["sim"]["strokes"].get<std::size_t>(), j["sent"]["last_stroke_sent"].get<std::size_t>()) << j.dump();
  EXPECT_NE(r.err.find("--resume-from " + std::to_string(j["sent"]["last_stroke_sent"].get<std::size_t>() + 1)),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(j["sent"]["complete"].get<bool>());
  EXPECT_EQ(j["sent"]["error"], "disconnected");
}

TEST_F(Cli, CutToAFileWritesTheSameBytes) {
  const fs::path out = dir_ / "cut", dev = dir_ / "device.hpgl";
  const Result r = run("cut " + example("voxel/box.json") + " --device file:" + dev.string() + " --profile " +
                       profile("generic-hpgl.toml") + " --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(dev), slurp(out / "job.hpgl")) << "the device got exactly the job";
  const Result empty = run("cut " + example("voxel/box.json") + " --device file: --profile " +
                           profile("generic-hpgl.toml") + " --out " + out.string());
  EXPECT_EQ(empty.code, 2) << "file: without a path is a bad command line: " << empty.err;
  EXPECT_NE(empty.err.find("--device: file: needs a path"), std::string::npos) << empty.err;
  // A profile that paces by XON/XOFF or ESC.B queries: a file cannot answer, so it is not asked.
  for (const char* paced : {"sim.toml", "secabo.toml"}) {
    const Result q = run("cut " + example("voxel/box.json") + " --device file:" + dev.string() + " --profile " +
                         profile(paced) + " --out " + out.string());
    ASSERT_EQ(q.code, 0) << paced << ": " << q.err;
    EXPECT_EQ(slurp(dev), slurp(out / "job.hpgl")) << paced << ": the file got exactly the job";
  }
}

}  // namespace
