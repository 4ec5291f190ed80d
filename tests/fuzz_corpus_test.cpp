// The fuzzers' seed corpora (fuzz/corpus) and every reproducer saved there
// replayed through the parsers in the normal build: each input either parses
// or fails with a DataError that says where.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/common/error.h"
#include "core/io/point_cloud_reader.h"
#include "core/io/point_grid_reader.h"
#include "core/machine/program_reader.h"
#include "lua_api/runner.h"
#include "machine/test_machines.h"
#include "test_support.h"

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

// point_cloud_reader_fuzz: the first byte picks the format, the rest is the file.
TEST(FuzzCorpus, PointCloudInputsParseOrSayWhere) {
  const auto files = corpus("point_cloud");
  ASSERT_GE(files.size(), 8u);
  int parsed = 0;
  std::string refused;
  for (const auto& [name, bytes] : files) {
    if (bytes.empty()) continue;
    PointCloudReadOptions o;
    o.format = static_cast<PointCloudFormat>(static_cast<unsigned char>(bytes[0]) % 5);
    try {
      const PointCloud c = parse_point_cloud(bytes.substr(1), name, o);
      EXPECT_FALSE(c.points.empty()) << name;
      ++parsed;
    } catch (const DataError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(name + ":", 0), 0u) << e.what();
      refused += std::string(e.what()) + "\n";
    }
  }
  EXPECT_GE(parsed, 8) << refused;  // every seed but bad.ply
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

// Machine-definition seeds (machine_definition_fuzz): loaded as a machine
// file, a valid table gives a machine; an invalid one fails at the machine
// file's line, naming the key.
TEST(FuzzCorpus, MachineDefinitionsLoadOrSayWhere) {
  const auto files = corpus("machine");
  ASSERT_GE(files.size(), 3u);
  int loaded = 0, refused = 0;
  for (const auto& [name, body] : files) {
    test::TempDir dir;
    std::ofstream(dir.path() + "/fuzz_machine.lua") << "return machine {" << body << "}\n";
    const test::RecipeResult r =
        test::run_recipe_text(dir, "local m = bliskrun.machine.load('fuzz_machine.lua')\nprint(m:name())\n");
    if (r.exit_code == 0) {
      ++loaded;
    } else {
      EXPECT_EQ(r.exit_code, 1) << name << ": " << r.output;
      EXPECT_NE(r.output.find("fuzz_machine.lua:1"), std::string::npos) << name << ": " << r.output;
      ++refused;
    }
  }
  EXPECT_GE(loaded, 2);   // the two complete definitions
  EXPECT_GE(refused, 2);  // bad.txt, short.txt
}

// Lua API seeds (lua_api_fuzz): each plan of calls through the API walk
// recipe ends normally, every call having returned or raised a Lua error.
TEST(FuzzCorpus, LuaApiPlansEndNormally) {
  const auto files = corpus("lua_api");
  ASSERT_GE(files.size(), 3u);
  for (const auto& [name, bytes] : files) {
    test::TempDir dir;
    std::string plan = "p";
    static const char* hex = "0123456789abcdef";
    for (unsigned char c : bytes) plan += std::string{hex[c >> 4], hex[c & 15]};
    lua_api::RunOptions o;
    o.recipe_path = std::string(BLISKRUN_SOURCE_DIR) + "/tests/lua_api/api_fuzz/api_walk.lua";
    o.out_dir = dir.path() + "/out";
    o.quiet = true;
    o.time_limit_s = 60;
    o.sets = {{"plan", plan}};
    std::ostringstream err;
    EXPECT_EQ(lua_api::run_recipe(o, err), 0) << name << ": " << err.str();
  }
}

}  // namespace
}  // namespace bliskrun
