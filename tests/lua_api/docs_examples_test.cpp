// Every ```lua block of docs/lua_api.md is a complete recipe; each must run.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "test_support.h"

namespace bliskrun::test {
namespace {

std::vector<std::pair<int, std::string>> lua_blocks(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::pair<int, std::string>> blocks;
  std::string line, block;
  int line_no = 0, start = 0;
  bool inside = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (!inside && line == "```lua") {
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

}  // namespace
}  // namespace bliskrun::test
