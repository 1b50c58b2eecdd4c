// Patterns drawn elsewhere on the kiosk page (headless Chromium over WebDriver) and on POST /api/v1/import/drawing.
#include <gtest/gtest.h>

#include <fstream>

#include "kiosk_browser.h"
#include "popcutd_process.h"

namespace {
using nlohmann::json;
using popcut::testing::Browser;
using popcut::testing::get_json;
using popcut::testing::kRendered;
using popcut::testing::PopcutdProcess;
using popcut::testing::TempDir;
using popcut::testing::wait_until;

const std::string kSrc = POPCUT_SOURCE_DIR;
const std::string kKiosk = "kiosk-change-me-0123456789";

std::string text_of(Browser& b, const std::string& id) {
  return b.run("return document.getElementById('" + id + "').textContent").get<std::string>();
}

bool shown(Browser& b, const std::string& id) {
  return !b.run("return document.getElementById('" + id + "').hidden").get<bool>();
}

void upload(Browser& b, const std::string& path) {
  const json input = b.session("POST", "/element", {{"using", "css selector"}, {"value", "#upload"}});
  b.session("POST", "/element/" + input.begin().value().get<std::string>() + "/value", {{"text", path}});
}

// The job at the top of the page once it has finished, and its state.
std::string finished_state(Browser& b) {
  std::string state;
  wait_until(
      [&] {
        state =
            b.run("const j = document.querySelector('#jobs .job'); return j ? j.dataset.state : ''").get<std::string>();
        return state == "done" || state == "failed" || state == "cancelled";
      },
      300);
  return state;
}

TEST(KioskDrawing, ReadsADrawnCardAndADrawnBoxAndCutsBoth) {
  TempDir dir("popcut-kiosk-drawing");
  PopcutdProcess d(POPCUTD, kSrc + "/configs/popcutd.toml", (dir.path() / "data").string());
  Browser b((dir.path() / "chromium").string());
  b.session("POST", "/url", {{"url", "http://127.0.0.1:" + std::to_string(d.port()) + "/?token=" + kKiosk}});
  ASSERT_TRUE(wait_until(
      [&] { return b.run("return document.querySelectorAll('#device option').length").get<int>() == 2; }, 60));

  // An OA card drawn in a vector editor: read as a card, it pops up like any model.
  upload(b, kSrc + "/examples/drawn/step.svg");
  ASSERT_TRUE(wait_until([&] { return !b.run("return document.getElementById('queue').disabled").get<bool>(); }, 120))
      << "the drawing is read and can be queued; page: " << b.run("return document.body.innerText").dump();
  EXPECT_TRUE(shown(b, "drawing")) << "the drawing's options show";
  EXPECT_EQ(text_of(b, "model-name").rfind("step.svg: a pop-up card of ", 0), 0u) << text_of(b, "model-name");
  EXPECT_TRUE(shown(b, "angle")) << "a card opens to the slider's angle";
  ASSERT_TRUE(wait_until([&] { return b.run(kRendered + "return rendered('preview')").get<bool>(); }, 60));
  b.click("#queue");
  EXPECT_EQ(finished_state(b), "done") << b.run("return document.body.innerText").dump();
  httplib::Client admin = d.client("admin-change-me-0123456789");
  const int card_id = std::stoi(b.run("return document.querySelector('#jobs .job').dataset.id").get<std::string>());

  // The box dieline read as a sheet: drawn as it is, its tabs pass through the walls...
  // Choosing "sheet" reads the drawing shown again; the box then replaces it.
  b.click("#read-as option[value='sheet']");
  upload(b, kSrc + "/examples/drawn/box.svg");
  ASSERT_TRUE(wait_until([&] { return text_of(b, "model-name").rfind("box.svg: a sheet of 11 panels", 0) == 0; }, 120))
      << b.run("return document.body.innerText").dump();
  EXPECT_FALSE(shown(b, "angle")) << "a sheet has no opening angle";
  EXPECT_TRUE(shown(b, "folded"));
  EXPECT_EQ(b.run("return document.getElementById('preview').src.slice(0, 22)").get<std::string>(),
            "data:image/png;base64,")
      << "the folded box shows";
  ASSERT_TRUE(wait_until(
      [&] {
        return b.run("const i = document.getElementById('preview'); return i.complete && i.naturalWidth > 100")
            .get<bool>();
      },
      60))
      << "the picture decodes";
  EXPECT_NE(text_of(b, "model-warning").find("pass through each other"), std::string::npos)
      << "the collision is said: " << text_of(b, "model-warning");
  // ... and folded in two stages, walls first, it closes cleanly.
  b.run("document.getElementById('fold').value = 'tab-*=90@2';");
  b.click("#reread");
  ASSERT_TRUE(wait_until([&] { return !b.run("return document.getElementById('queue').disabled").get<bool>(); }, 120));
  EXPECT_FALSE(shown(b, "model-warning")) << text_of(b, "model-warning");
  // Left in the build tree for a person to look at.
  b.run("window.scrollTo(0, 0);");
  std::ofstream(std::string(POPCUT_SCREENSHOT_DIR) + "/kiosk-drawing.png", std::ios::binary)
      << popcut::testing::base64_decode(b.session("GET", "/screenshot").get<std::string>());
  b.click("#queue");
  ASSERT_TRUE(wait_until(
      [&] {
        const std::string id = b.run("return document.querySelector('#jobs .job').dataset.id").get<std::string>();
        return std::stoi(id) != card_id;
      },
      60));
  EXPECT_EQ(finished_state(b), "done") << b.run("return document.body.innerText").dump();
  const std::string box_id = b.run("return document.querySelector('#jobs .job').dataset.id").get<std::string>();
  const json box = get_json(admin, "/api/v1/jobs/" + box_id).body;
  EXPECT_EQ(box["name"], "box") << box.dump();
  EXPECT_GT(box["strokes_total"].get<int>(), 10) << "the outline and the scored creases were cut";

  // A drawing that folds into no card says which faces conflict, and nothing stays to queue.
  b.click("#read-as option[value='card']");
  ASSERT_TRUE(wait_until([&] { return shown(b, "model-error"); }, 120));
  EXPECT_NE(text_of(b, "model-error").find("no OA card folds from this sheet"), std::string::npos)
      << text_of(b, "model-error");
  EXPECT_TRUE(b.run("return document.getElementById('queue').disabled").get<bool>());
}

// The route itself: every bad field and bad drawing is a precise 4xx, never a crash or a guess.
TEST(KioskDrawing, TheDrawingRouteRefusesBadInputByName) {
  TempDir dir("popcut-drawing-route");
  PopcutdProcess d(POPCUTD, kSrc + "/configs/popcutd.toml", (dir.path() / "data").string());
  httplib::Client c = d.client(kKiosk);
  const auto post = [&](httplib::MultipartFormDataItems items) {
    const auto r = c.Post("/api/v1/import/drawing", items);
    EXPECT_TRUE(r) << "popcutd answers";
    return std::make_pair(r ? r->status : 0, r ? json::parse(r->body, nullptr, false) : json());
  };
  const std::string svg =
      "<svg xmlns='http://www.w3.org/2000/svg' width='100mm' height='60mm' viewBox='0 0 100 60'>"
      "<rect x='0' y='0' width='100' height='60' fill='none' stroke='black'/></svg>";
  struct Case {
    httplib::MultipartFormDataItems items;
    int status;
    std::string field, says;
  };
  const std::vector<Case> cases = {
      {{{"as", "card", "", ""}}, 400, "drawing", "missing the 'drawing'"},
      {{{"drawing", svg, "a.png", "image/png"}}, 400, "drawing", "not a drawing popcut reads"},
      {{{"drawing", svg, "a.svg", "image/svg+xml"}, {"as", "origami", "", ""}}, 400, "as", "card or sheet"},
      {{{"drawing", svg, "a.svg", ""}, {"unit-mm", "nan", "", ""}}, 400, "unit-mm", "a number from"},
      {{{"drawing", svg, "a.svg", ""}, {"fold", "tab-*=90", "", ""}}, 400, "fold", "with as=sheet"},
      {{{"drawing", svg, "a.svg", ""}, {"as", "sheet", "", ""}, {"fold", "tab=ninety", "", ""}},
       400,
       "fold",
       "LINE=DEGREES"},
      {{{"drawing", svg, "a.svg", ""}, {"as", "sheet", "", ""}, {"fold", "nosuch=90", "", ""}}, 400, "fold", "nosuch"},
      {{{"drawing", svg, "a.svg", ""}, {"snap-mm", "0x1", "", ""}}, 400, "snap-mm", "a number from"},
      {{{"drawing", svg, "a.svg", ""}, {"colour", "red", "", ""}}, 400, "colour", "unknown field"},
      {{{"drawing", svg, "a.svg", ""}, {"as", "card", "", ""}, {"as", "sheet", "", ""}}, 400, "as", "given twice"},
      {{{"drawing", "<svg><g>", "a.svg", ""}}, 422, "drawing", "a.svg"},
      {{{"drawing", "{\"vertices_coords\": 5}", "a.fold", ""}}, 422, "drawing", "vertices_coords"},
      {{{"drawing", "0\nSECTION\n2\nENTITIES\n0\nLINE\n8\nCUT\n10\nabc\n", "a.dxf", ""}}, 422, "drawing", "a.dxf"},
  };
  for (const Case& k : cases) {
    const auto [status, body] = post(k.items);
    EXPECT_EQ(status, k.status) << body.dump();
    ASSERT_TRUE(body.contains("error")) << body.dump();
    EXPECT_EQ(body["error"]["field"], k.field) << body.dump();
    EXPECT_NE(body["error"]["message"].get<std::string>().find(k.says), std::string::npos) << body.dump();
  }
  // A sheet with nothing wrong: its lines, a picture, no problems.
  const auto [status, body] = post({{"drawing", svg, "plain.svg", ""}, {"as", "sheet", "", ""}});
  ASSERT_EQ(status, 200) << body.dump();
  EXPECT_EQ(body["format"], "popcut.pattern.v1");
  EXPECT_EQ(body["regions"], 1);
  EXPECT_EQ(body["folds"], true);
  EXPECT_EQ(body["sheet_mm"]["width"], 100);
  EXPECT_EQ(body["name"], "plain");
}

}  // namespace
