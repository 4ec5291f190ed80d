// The fuzzers' seed corpora (fuzz/corpus) and every reproducer saved there
// replayed through the parsers in the normal build: each input either parses
// or fails with a DataError that says where.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/common/error.h"
#include "core/io/point_grid_reader.h"
#include "core/machine/program_reader.h"
#include "machine/test_machines.h"

namespace bliskrun {
namespace {

namespace fs = std::filesystem;

std::vector<std::pair<std::string, std::string>> corpus(const std::string& name) {
  std::vector<std::pair<std::string, std::string>> files;
  for (const auto& e : fs::directory_iterator(fs::path(BLISKRUN_SOURCE_DIR) / "fuzz" / "corpus" / name)) {
    std::ifstream in(e.path(), std::ios::binary);
    files.emplace_back(e.path().filename().string(), std::string((std::istreambuf_iterator<char>(in)), {}));
  }
  return files;
}

TEST(FuzzCorpus, PointGridInputsParseOrSayWhere) {
  const auto files = corpus("point_grid");
  ASSERT_FALSE(files.empty());
  for (const auto& [name, text] : files) {
    try {
      const PointGrid g = parse_point_grid(text, name);
      EXPECT_EQ(g.points.size(), static_cast<size_t>(g.rows) * g.cols) << name;
    } catch (const DataError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(name + ":", 0), 0u) << e.what();
    }
  }
}

TEST(FuzzCorpus, ProgramInputsReadOrSayWhere) {
  const auto files = corpus("program");
  ASSERT_FALSE(files.empty());
  const MachineDefinition machine = test::table_table_ac();
  for (const auto& [name, text] : files) {
    ProgramReadOptions o;
    o.file_name = name;
    try {
      read_program(text, machine, o);
    } catch (const DataError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(name + ":", 0), 0u) << e.what();
    }
  }
}

}  // namespace
}  // namespace bliskrun
