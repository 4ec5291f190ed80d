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

std::string slurp(const fs::path& p) {
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
     table = {columns = {"flank", "rows", "undercut max (um)"}, rows = {{"pressure", 32, 14.25}, {"suction", 30, 13.5}}}},
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
  const std::string html = slurp(fs::path(dir.path()) / "out" / "report.html");
  expect_well_formed_and_self_contained(html);
  EXPECT_NE(html.find("<title>Test &lt;run&gt;</title>"), std::string::npos);
  EXPECT_NE(html.find("<li><a href=\"#s2\">Pictures</a></li>"), std::string::npos);
  EXPECT_NE(html.find("<p>First paragraph &amp; more.</p>"), std::string::npos);
  EXPECT_NE(html.find("<th>undercut max (um)</th>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"n\">14.25</td>"), std::string::npos);
  EXPECT_EQ(html.find("<?xml"), std::string::npos);  // the SVG's declaration is dropped
  EXPECT_NE(html.find("<svg"), std::string::npos);
  // The PNG inlined is the file, byte for byte (base64 of its 8-byte signature).
  EXPECT_NE(html.find("src=\"data:image/png;base64,iVBORw0KGgo"), std::string::npos);
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
  const std::string d = slurp(dom);
  size_t rows = 0;
  for (size_t p = d.find("<tr>"); p != std::string::npos; p = d.find("<tr>", p + 1)) ++rows;
  EXPECT_EQ(rows, 3u);  // heading + 2 rows
  EXPECT_NE(d.find("data:image/png;base64,"), std::string::npos);
  EXPECT_NE(d.find("<svg"), std::string::npos);
  ASSERT_EQ(std::system((browser + flags + "--screenshot=" + shot.string() + " --window-size=1200,1600 file://" +
                         page.string() + " >/dev/null 2>&1").c_str()), 0);
  EXPECT_GT(fs::file_size(shot), 10000u);
}

}  // namespace
}  // namespace bliskrun
