// Every ```lua block of every page under docs/ (the tutorial, the Lua API
// index and its topic pages in docs/lua_api/, ...) is a complete recipe; each
// must run. Blocks fenced ```lua needs-data read real part data: they run with
// --data ../shared/data when it is present and are skipped otherwise. The
// pages are found by walking docs/, so a new page's examples run without
// touching this file.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "test_support.h"

namespace bliskrun::test {
namespace {

struct Block {
  std::string where;  // docs/<page>.md:<first line of the code>
  std::string code;
};

std::vector<Block> lua_blocks(const std::filesystem::path& path, const std::string& shown,
                              const std::string& fence) {
  std::ifstream in(path);
  std::vector<Block> blocks;
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
      blocks.push_back({shown + ":" + std::to_string(start), block});
    } else if (inside) {
      block += line + "\n";
    }
  }
  return blocks;
}

// The blocks of every docs/**/*.md, pages in path order.
std::vector<Block> docs_blocks(const std::string& fence) {
  const std::filesystem::path docs = std::filesystem::path(BLISKRUN_SOURCE_DIR) / "docs";
  std::vector<std::filesystem::path> pages;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(docs)) {
    if (entry.is_regular_file() && entry.path().extension() == ".md") pages.push_back(entry.path());
  }
  std::sort(pages.begin(), pages.end());
  std::vector<Block> blocks;
  for (const auto& page : pages) {
    const std::string shown = "docs/" + page.lexically_relative(docs).generic_string();
    for (auto& b : lua_blocks(page, shown, fence)) blocks.push_back(std::move(b));
  }
  return blocks;
}

std::size_t count_from(const std::vector<Block>& blocks, const std::string& page) {
  return std::count_if(blocks.begin(), blocks.end(),
                       [&](const Block& b) { return b.where.rfind(page + ":", 0) == 0; });
}

TEST(DocsExamples, EveryLuaBlockRuns) {
  const auto blocks = docs_blocks("```lua");
  // 47 when docs/lua_api.md was split into topic pages, plus the tutorial's.
  ASSERT_GE(blocks.size(), 49u) << "docs/ lost examples";
  EXPECT_GE(count_from(blocks, "docs/tutorial.md"), 2u) << "the tutorial lost its recipes";
  for (const auto& [where, code] : blocks) {
    TempDir dir;
    const RecipeResult r = run_recipe_text(dir, code);
    EXPECT_EQ(r.exit_code, 0) << where << ": example failed:\n" << r.output;
  }
}

TEST(DocsExamples, EveryRealDataBlockRuns) {
  const auto blocks = docs_blocks("```lua needs-data");
  ASSERT_GE(blocks.size(), 1u) << "docs/ lost its real-data examples";
  const std::string data = shared_data_dir();
  if (data.empty()) GTEST_SKIP() << "../shared/data not present: real-data examples skipped";
#ifdef BLISKRUN_SANITIZED
  // Full-size reads and plans of the real parts (~130 s under the
  // sanitizers): like the recipe runs, left to the Release suite; the
  // readers and the Lua API they call run here in their own tests.
  GTEST_SKIP() << "real-data examples run in the Release suite, not under the sanitizers";
#endif
  for (const auto& [where, code] : blocks) {
    TempDir dir;
    const std::string recipe = dir.write("recipe.lua", code);
    const RecipeResult r = run_bliskrun({recipe, "--data", data, "--out", dir.path() + "/out", "--quiet"});
    EXPECT_EQ(r.exit_code, 0) << where << ": example failed:\n" << r.output;
  }
}

}  // namespace
}  // namespace bliskrun::test
