#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <vector>

#include "test_support.h"

namespace bliskrun {
namespace {

namespace fs = std::filesystem;

std::string slurp_report(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const char* kReportRecipe = R"LUA(
local map = bliskrun.blisk{}:flank_grid(1, "pressure"):surface()
local st = bliskrun.curvature_stats(map, {samples_u = 20, samples_v = 40})
st.map:write_png("k.png", {width = 200, height = 100})
local svg = st.map:write_svg("k.svg", {width = 200, height = 100})
bliskrun.report{path = "report.html", title = "Test <run>", subtitle = "two sections",
  sections = {
    {title = "Numbers", text = {"First paragraph & more.", "Second."},
     table = {columns = {"flank", "rows", "undercut max (um)"}, rows = {{"pressure", 32, 14.26}, {"suction", 30, 1234.56}}}},
    {title = "Pictures", svg = bliskrun.read_text(svg), image = "k.png", caption = "K over (u, v)"},
  }}
)LUA";

// Tag balance of the HTML we write (void elements excepted), and no
// reference that leaves the file.
void expect_well_formed_and_self_contained(const std::string& html) {
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  std::vector<std::string> stack;
  const std::regex tag("<(/?)([a-zA-Z][a-zA-Z0-9]*)[^>]*?(/?)>");
  for (std::sregex_iterator it(html.begin(), html.end(), tag), end; it != end; ++it) {
    const std::string name = (*it)[2];
    if (name == "meta" || name == "img" || name == "br" || (*it)[3] == "/") continue;
    if ((*it)[1] == "/") {
      ASSERT_FALSE(stack.empty()) << "closing " << name << " with nothing open";
      ASSERT_EQ(stack.back(), name) << "at offset " << it->position();
      stack.pop_back();
    } else {
      stack.push_back(name);
    }
  }
  EXPECT_TRUE(stack.empty());
  const std::regex ref("(src|href)=\"([^\"]*)\"");
  int refs = 0;
  for (std::sregex_iterator it(html.begin(), html.end(), ref), end; it != end; ++it, ++refs) {
    const std::string target = (*it)[2];
    EXPECT_TRUE(target.rfind("#", 0) == 0 || target.rfind("data:image/png;base64,", 0) == 0) << target;
  }
  EXPECT_GT(refs, 0);
  EXPECT_EQ(html.find("<script"), std::string::npos);
}

TEST(Report, WellFormedSelfContainedPageWithTocTablesChartsAndPictures) {
  test::TempDir dir;
  const auto r = test::run_recipe_text(dir, kReportRecipe);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string html = slurp_report(fs::path(dir.path()) / "out" / "report.html");
  expect_well_formed_and_self_contained(html);
  EXPECT_NE(html.find("<title>Test &lt;run&gt;</title>"), std::string::npos);
  EXPECT_NE(html.find("<li><a href=\"#s2\">Pictures</a></li>"), std::string::npos);
  EXPECT_NE(html.find("<p>First paragraph &amp; more.</p>"), std::string::npos);
  EXPECT_NE(html.find("<th>undercut max (um)</th>"), std::string::npos);
  // Numbers to 3 significant digits, no exponent, integers as they are.
  EXPECT_NE(html.find("<td class=\"n\">14.3</td>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"n\">1235</td>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"n\">32</td>"), std::string::npos);
  // No verdict given to bliskrun.report: none drawn.
  EXPECT_EQ(html.find("id=\"verdict\""), std::string::npos);
  EXPECT_EQ(html.find("<?xml"), std::string::npos);  // the SVG's declaration is dropped
  EXPECT_NE(html.find("<svg"), std::string::npos);
  // The PNG inlined is the file, byte for byte (base64 of its 8-byte signature).
  EXPECT_NE(html.find("src=\"data:image/png;base64,iVBORw0KGgo"), std::string::npos);
}

// run_report.write: the verdict first, PASS or FAIL per requirement with
// its limit and measured value; a failed one fails the run after the page
// and the JSON (verdict first there too) are written.
std::string verdict_recipe(const char* overcut_tol_um) {
  return std::string("local tiny = ") + overcut_tol_um + R"LUA(
local run_report = require("run_report")
local verdict = run_report.verdict{
  {name = "overcut: deepest cut below the design", unit = "µm", measured = 0.0013089e3, at_most = tiny},
  {name = "material left", unit = "µm", measured = 12.345, at_most = 20},
  {name = "refused poses", unit = "count", measured = 0, at_most = 0},
}
bliskrun.write_json("run.json", {a = 1, verdict = verdict, z = {b = 2}})
run_report.write{title = "Verdict test", verdict = verdict, sections = {{title = "Numbers", text = "x"}}}
)LUA";
}

TEST(Report, VerdictFirstPassesWithinTheTolerances) {
  test::TempDir dir;
  const auto r = test::run_recipe_text(dir, verdict_recipe("5"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string html = slurp_report(fs::path(dir.path()) / "out" / "report.html");
  expect_well_formed_and_self_contained(html);
  const size_t verdict = html.find("<section id=\"verdict\" class=\"verdict pass\">");
  ASSERT_NE(verdict, std::string::npos);
  EXPECT_LT(verdict, html.find("<nav>"));  // above the table of contents
  EXPECT_NE(html.find("Verdict: <strong>PASS</strong>"), std::string::npos);
  EXPECT_NE(html.find("<td>material left</td><td>µm</td><td class=\"n\">&le; 20.0</td><td class=\"n\">12.3</td>"
                      "<td>PASS</td>"), std::string::npos) << html;
  EXPECT_NE(html.find("<td class=\"n\">1.31</td>"), std::string::npos);
  // The JSON report starts with the verdict; the other keys stay sorted.
  const std::string json = slurp_report(fs::path(dir.path()) / "out" / "run.json");
  EXPECT_EQ(json.find("{\n  \"verdict\": {"), 0u) << json.substr(0, 80);
  EXPECT_LT(json.find("\"a\": 1"), json.find("\"z\""));
  EXPECT_NE(json.find("\"overall\": \"PASS\""), std::string::npos);
}

TEST(Report, VerdictFailsWhenATolerancesIsExceededAndTheRunExitsNonZeroAfterThePage) {
  test::TempDir dir;
  // A tolerance of 1 µm on an overcut of 1.31 µm.
  const auto r = test::run_recipe_text(dir, verdict_recipe("1"));
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("verdict FAIL: overcut: deepest cut below the design 1.31 µm (limit <= 1 µm)"),
            std::string::npos) << r.output;
  const std::string html = slurp_report(fs::path(dir.path()) / "out" / "report.html");
  EXPECT_NE(html.find("Verdict: <strong>FAIL</strong>"), std::string::npos);
  EXPECT_NE(html.find("<tr class=\"fail\"><td>overcut: deepest cut below the design</td>"), std::string::npos);
  EXPECT_NE(html.find("<tr class=\"pass\"><td>material left</td>"), std::string::npos);
  const std::string json = slurp_report(fs::path(dir.path()) / "out" / "run.json");
  EXPECT_NE(json.find("\"overall\": \"FAIL\""), std::string::npos);
}

class ReportErrors : public ::testing::TestWithParam<test::RecipeErrorCase> {};
TEST_P(ReportErrors, NameTheLineAndTheKey) {
  test::TempDir dir;
  EXPECT_TRUE(test::fails_at_line_2(dir, GetParam()));
}
INSTANTIATE_TEST_SUITE_P(
    Cases, ReportErrors,
    ::testing::Values(
        test::RecipeErrorCase{"NotHtml", "bliskrun.report{path = 'r.txt', title = 't', sections = {}}", "expected an .html"},
        test::RecipeErrorCase{"RowLength",
                              "bliskrun.report{path = 'r.html', title = 't', sections = {{title = 'a', table = "
                              "{columns = {'x', 'y'}, rows = {{1}}}}}}",
                              "sections[1].table.rows[1]: expected 2 cells"},
        test::RecipeErrorCase{"NoImage",
                              "bliskrun.report{path = 'r.html', title = 't', sections = {{title = 'a', image = 'none.png'}}}",
                              "sections[1].image: cannot read 'none.png'"},
        test::RecipeErrorCase{"NotSvg",
                              "bliskrun.report{path = 'r.html', title = 't', sections = {{title = 'a', svg = 'hello'}}}",
                              "expected an SVG document"},
        test::RecipeErrorCase{"UnknownKey",
                              "bliskrun.report{path = 'r.html', title = 't', sections = {{title = 'a', chart = 1}}}",
                              "chart"}),
    test::error_case_name);

// Opens the page in headless Chromium (installed by .ci/install-deps' test
// extras): the DOM it builds holds the tables and the pictures, and it
// renders a screenshot.
TEST(Report, OpensInHeadlessChromium) {
  std::string browser;
  for (const char* b : {"/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome"})
    if (fs::exists(b)) browser = b;
  if (browser.empty())
    GTEST_SKIP() << "no Chromium found (install it with `CI=true .ci/install-deps` or `.ci/install-deps --test-extras`)";
  test::TempDir dir;
  const auto r = test::run_recipe_text(dir, kReportRecipe);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path page = fs::path(dir.path()) / "out" / "report.html";
  const fs::path dom = fs::path(dir.path()) / "dom.html", shot = fs::path(dir.path()) / "shot.png";
  const std::string flags = " --headless --no-sandbox --disable-gpu --user-data-dir=" + dir.path() + "/profile ";
  ASSERT_EQ(std::system((browser + flags + "--dump-dom file://" + page.string() + " > " + dom.string() +
                         " 2>/dev/null").c_str()), 0);
  const std::string d = slurp_report(dom);
  size_t rows = 0;
  for (size_t p = d.find("<tr>"); p != std::string::npos; p = d.find("<tr>", p + 1)) ++rows;
  EXPECT_EQ(rows, 3u);  // heading + 2 rows
  // A run_report page: the verdict's text is in the DOM before the
  // contents, so it is the first thing on screen.
  test::TempDir verdict_dir;
  ASSERT_EQ(test::run_recipe_text(verdict_dir, verdict_recipe("5")).exit_code, 0);
  const fs::path verdict_dom = fs::path(verdict_dir.path()) / "dom.html";
  ASSERT_EQ(std::system((browser + " --headless --no-sandbox --disable-gpu --user-data-dir=" + verdict_dir.path() +
                         "/profile --dump-dom file://" + verdict_dir.path() + "/out/report.html > " +
                         verdict_dom.string() + " 2>/dev/null").c_str()), 0);
  const std::string vd = slurp_report(verdict_dom);
  ASSERT_NE(vd.find("Verdict: <strong>PASS</strong>"), std::string::npos);
  EXPECT_LT(vd.find("Verdict: <strong>PASS</strong>"), vd.find("<nav>"));
  EXPECT_NE(d.find("data:image/png;base64,"), std::string::npos);
  EXPECT_NE(d.find("<svg"), std::string::npos);
  ASSERT_EQ(std::system((browser + flags + "--screenshot=" + shot.string() + " --window-size=1200,1600 file://" +
                         page.string() + " >/dev/null 2>&1").c_str()), 0);
  EXPECT_GT(fs::file_size(shot), 10000u);
}

}  // namespace
}  // namespace bliskrun
