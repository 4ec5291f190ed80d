// The one toolpath type (core/toolpath): passes split where the program
// stops, and the APT/CL body, against literal expected text.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "core/toolpath/apt.h"
#include "core/toolpath/move.h"

namespace bliskrun {
namespace {

Move move_at(Move::Kind kind, double x, int row, const char* motion) {
  Move m;
  m.kind = kind;
  m.pose.tip = Vec3(x, 0, 0);
  m.row = row;
  m.motion = motion;
  return m;
}

Move stop(int row, const char* reason) {
  Move m;
  m.kind = Move::Kind::Stop;
  m.row = row;
  m.motion = "stop";
  m.reason = reason;
  return m;
}

// lead-in, row 0 (2 feeds), a link (rapid), row 1 (2 feeds), a refused
// link, row 2 (1 feed), lead-out.
Toolpath program() {
  return {move_at(Move::Kind::Rapid, 0, 0, "start"), move_at(Move::Kind::Feed, 1, 0, "approach"),
          move_at(Move::Kind::Feed, 2, 0, "cut"),    move_at(Move::Kind::Rapid, 3, 1, "traverse"),
          move_at(Move::Kind::Feed, 4, 1, "approach"), move_at(Move::Kind::Feed, 5, 1, "cut"),
          stop(2, "link: blocked"),            move_at(Move::Kind::Feed, 6, 2, "start"),
          move_at(Move::Kind::Rapid, 7, 2, "retract")};
}

TEST(Toolpath, PassesEndAtStopsAndNameTheirFirstMove) {
  const Toolpath moves = program();
  const ToolpathPasses p = toolpath_passes(moves);
  ASSERT_EQ(p.passes.size(), 2u);
  ASSERT_EQ(p.first_move.size(), 2u);
  EXPECT_EQ(p.first_move[0], 0);
  EXPECT_EQ(p.first_move[1], 7);
  ASSERT_EQ(p.passes[0].size(), 6u);
  ASSERT_EQ(p.passes[1].size(), 2u);
  // Pose k of pass p is move first_move[p] + k: what a simulation result
  // (pass, pose) is traced back with.
  for (size_t k = 0; k < p.passes.size(); ++k)
    for (size_t i = 0; i < p.passes[k].size(); ++i)
      EXPECT_EQ(p.passes[k][i].tip, moves[static_cast<size_t>(p.first_move[k]) + i].pose.tip) << k << " " << i;
  // Stops only (or nothing): no pass.
  EXPECT_TRUE(toolpath_passes({stop(0, "lead-in: blocked")}).passes.empty());
  EXPECT_TRUE(toolpath_passes({}).first_move.empty());
}

TEST(Toolpath, AptBodyWritesRapidsRowHeadersAndStops) {
  std::ostringstream os;
  write_apt_moves(os, program(), [](int row) { return "$$ ROW " + std::to_string(row) + "\n"; }, "LINK REFUSED");
  const char* expected =
      "RAPID\n"
      "GOTO/0.000000,0.000000,0.000000,0.000000,0.000000,1.000000\n"
      "$$ ROW 0\n"
      "GOTO/1.000000,0.000000,0.000000,0.000000,0.000000,1.000000\n"
      "GOTO/2.000000,0.000000,0.000000,0.000000,0.000000,1.000000\n"
      "RAPID\n"
      "GOTO/3.000000,0.000000,0.000000,0.000000,0.000000,1.000000\n"
      "$$ ROW 1\n"
      "GOTO/4.000000,0.000000,0.000000,0.000000,0.000000,1.000000\n"
      "GOTO/5.000000,0.000000,0.000000,0.000000,0.000000,1.000000\n"
      "$$ LINK REFUSED: link: blocked\n"
      "STOP\n"
      "$$ ROW 2\n"
      "GOTO/6.000000,0.000000,0.000000,0.000000,0.000000,1.000000\n"
      "RAPID\n"
      "GOTO/7.000000,0.000000,0.000000,0.000000,0.000000,1.000000\n";
  EXPECT_EQ(os.str(), expected);
}

TEST(Toolpath, KindNames) {
  EXPECT_STREQ(to_string(Move::Kind::Feed), "feed");
  EXPECT_STREQ(to_string(Move::Kind::Rapid), "rapid");
  EXPECT_STREQ(to_string(Move::Kind::Stop), "stop");
}

}  // namespace
}  // namespace bliskrun
