// Every ```lua block of docs/lua_api.md is a complete recipe; each must run.
// Blocks fenced ```lua needs-data read real part data: they run with
// --data ../shared/data when it is present and are skipped otherwise.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "test_support.h"

namespace bliskrun::test {
namespace {

std::vector<std::pair<int, std::string>> lua_blocks(const std::string& path, const std::string& fence = "```lua") {
  std::ifstream in(path);
  std::vector<std::pair<int, std::string>> blocks;
  std::string line, block;
  int line_no = 0, start = 0;
  bool inside = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (!inside && line == fence) {
      inside = true;
      start = line_no + 1;
      block.clear();
    } else if (inside && line == "```") {
      inside = false;
      blocks.emplace_back(start, block);
    } else if (inside) {
      block += line + "\n";
    }
  }
  return blocks;
}

TEST(DocsExamples, EveryLuaBlockRuns) {
  const std::string doc = std::string(BLISKRUN_SOURCE_DIR) + "/docs/lua_api.md";
  const auto blocks = lua_blocks(doc);
  ASSERT_GE(blocks.size(), 6u) << "docs/lua_api.md lost its examples";
  for (const auto& [line, code] : blocks) {
    TempDir dir;
    const RecipeResult r = run_recipe_text(dir, code);
    EXPECT_EQ(r.exit_code, 0) << "docs/lua_api.md:" << line << ": example failed:\n" << r.output;
  }
}

TEST(DocsExamples, EveryRealDataBlockRuns) {
  const std::string doc = std::string(BLISKRUN_SOURCE_DIR) + "/docs/lua_api.md";
  const auto blocks = lua_blocks(doc, "```lua needs-data");
  ASSERT_GE(blocks.size(), 1u) << "docs/lua_api.md lost its real-data examples";
  const std::string data = shared_data_dir();
  if (data.empty()) GTEST_SKIP() << "../shared/data not present: real-data examples skipped";
  for (const auto& [line, code] : blocks) {
    TempDir dir;
    const std::string recipe = dir.write("recipe.lua", code);
    const RecipeResult r = run_bliskrun({recipe, "--data", data, "--out", dir.path() + "/out", "--quiet"});
    EXPECT_EQ(r.exit_code, 0) << "docs/lua_api.md:" << line << ": example failed:\n" << r.output;
  }
}

}  // namespace
}  // namespace bliskrun::test
