#include "core/machine/program_reader.h"

#include <gtest/gtest.h>

#include "core/common/error.h"
#include "machine/test_machines.h"

namespace bliskrun {
namespace {


ProgramReadOptions read_named(const std::string& file) {
  ProgramReadOptions o;
  o.file_name = file;
  return o;
}

std::string program_error_of(const std::string& text, const MachineDefinition& m) {
  try {
    read_program(text, m, read_named("prog.nc"));
  } catch (const DataError& e) {
    return e.what();
  }
  return "no error";
}

TEST(MachineProgramReader, ReadsAnIsoProgram) {
  const std::string text =
      "%\n"
      "O1000 (hand written)\n"
      "N10 G90 G94 G17 G21\n"
      "N20 T3 M6\n"
      "N30 G0 X10. Y-5.5 Z100. A0. C90.\n"
      "N40 G1 Z2.5 F800.\n"
      "\n"
      "N50 G93 G1 X12.345 A-30. C-45.5 F12.5\n"
      "N60 G43.4 H3\n"
      "N70 X1Y2Z3 ; packed words\n"
      "N80 G49 M30\n"
      "%\n";
  const auto moves = read_program(text, test::table_table_ac(), read_named("a.nc"));
  ASSERT_EQ(moves.size(), 4u);
  EXPECT_EQ(moves[0].line, 5);
  EXPECT_EQ(moves[0].kind, MoveKind::Rapid);
  EXPECT_EQ(moves[0].tool, 3);
  EXPECT_EQ(moves[0].axes.linear_mm, Vec3(10, -5.5, 100));
  EXPECT_NEAR(moves[0].axes.rotary_rad[1], 90 * kDeg, 1e-15);
  EXPECT_EQ(moves[1].line, 6);
  EXPECT_EQ(moves[1].kind, MoveKind::Feed);
  EXPECT_EQ(moves[1].axes.linear_mm, Vec3(10, -5.5, 2.5));  // modal X Y
  EXPECT_EQ(moves[1].feed, 800);
  EXPECT_EQ(moves[1].feed_mode, FeedMode::PerMinute);
  EXPECT_EQ(moves[2].line, 8);
  EXPECT_EQ(moves[2].feed_mode, FeedMode::InverseTime);
  EXPECT_EQ(moves[2].feed, 12.5);
  EXPECT_NEAR(moves[2].axes.rotary_rad[0], -30 * kDeg, 1e-15);
  EXPECT_NEAR(moves[2].axes.rotary_rad[1], -45.5 * kDeg, 1e-15);
  EXPECT_FALSE(moves[2].tcp);
  EXPECT_EQ(moves[3].line, 10);
  EXPECT_TRUE(moves[3].tcp);
  EXPECT_EQ(moves[3].axes.linear_mm, Vec3(1, 2, 3));
  EXPECT_EQ(moves[3].kind, MoveKind::Feed);
}

TEST(MachineProgramReader, ReadsHeidenhainAndSiemensBlocks) {
  const std::string heidenhain =
      "0 BEGIN PGM BLISK_BLADE_1_SUCTION MM\n"
      "1 TOOL CALL 3 Z S12000\n"
      "2 L X+10.000 Y-5.500 Z+100.000 B+0.000 C+90.000 R0 FMAX M3\n"
      "3 M128\n"
      "4 L Z+2.500 F800\n"
      "5 L X+12.345 B-30.000 C-45.500 R0 F500 ; comment\n"
      "6 FUNCTION RESET TCPM\n"
      "7 L Z+50 FMAX\n"
      "8 END PGM BLISK_BLADE_1_SUCTION MM\n";
  const auto h = read_program(heidenhain, test::head_table_bc(), read_named("h.h"));
  ASSERT_EQ(h.size(), 4u);
  EXPECT_EQ(h[0].kind, MoveKind::Rapid);
  EXPECT_EQ(h[0].tool, 3);
  EXPECT_FALSE(h[0].tcp);
  EXPECT_EQ(h[1].kind, MoveKind::Feed);
  EXPECT_TRUE(h[1].tcp);
  EXPECT_EQ(h[2].axes.linear_mm, Vec3(12.345, -5.5, 2.5));
  EXPECT_NEAR(h[2].axes.rotary_rad[1], -30 * kDeg, 1e-15);  // B is rotary[1] here
  EXPECT_EQ(h[2].feed, 500);
  EXPECT_EQ(h[3].kind, MoveKind::Rapid);
  EXPECT_FALSE(h[3].tcp);
  EXPECT_EQ(h[3].line, 8);

  const std::string siemens =
      "; 840D\n"
      "N10 T=\"\" \n";
  EXPECT_NE(program_error_of(siemens, test::table_table_ac()).find("prog.nc:2:"), std::string::npos);
  const std::string siemens_ok =
      "N10 T3 D1 M6\n"
      "N20 TRAORI\n"
      "N30 G1 X1 Y2 Z3 A4 C5 F100\n"
      "N40 TRAFOOF\n"
      "N50 G0 Z100\n"
      "N60 M30\n";
  const auto s = read_program(siemens_ok, test::table_table_ac(), read_named("s.mpf"));
  ASSERT_EQ(s.size(), 2u);
  EXPECT_TRUE(s[0].tcp);
  EXPECT_FALSE(s[1].tcp);
  EXPECT_NEAR(s[0].axes.rotary_rad[0], 4 * kDeg, 1e-15);
}

// The work offset a program selects by a block, in each dialect; the
// header's verdict line is a comment. A TNC cycle's parameters continue the
// block on the next line ("~"), and the block keeps its first line.
TEST(MachineProgramReader, ReadsTheWorkOffsetAProgramSelects) {
  const std::string heidenhain =
      "0 BEGIN PGM P MM\n"
      "1 ; VERDICT: @VERDICT@\n"
      "2 CYCL DEF 247 DATUM SETTING ~\n"
      "  Q339=+3    ;DATUM NUMBER\n"
      "3 TOOL CALL 3 Z S12000\n"
      "4 L X+1.000 Y+0.000 Z+30.000 B+0.000 C+0.000 R0 FMAX\n"
      "5 END PGM P MM\n";
  const auto h = read_program(heidenhain, test::head_table_bc(), read_named("h.h"));
  ASSERT_EQ(h.size(), 1u);
  EXPECT_EQ(h[0].work_offset, 3);
  EXPECT_EQ(h[0].line, 6);
  const auto no_preset = read_program("0 BEGIN PGM P MM\n1 L X+1 B+0 C+0 R0 FMAX\n", test::head_table_bc(), read_named("h.h"));
  EXPECT_EQ(no_preset[0].work_offset, 0);

  struct Case { const char* word; int offset; };
  for (const Case& c : {Case{"G54", 1}, Case{"G55", 2}, Case{"G59", 6}, Case{"G59.1", 7}, Case{"G59.3", 9},
                        Case{"G505", 5}, Case{"G599", 99}}) {
    const std::string iso = std::string("(VERDICT: @VERDICT@)\nN10 G90 ") + c.word + "\nN20 G0 X1 Y2 Z3\n";
    const auto moves = read_program(iso, test::table_table_ac(), read_named("a.nc"));
    ASSERT_EQ(moves.size(), 1u) << c.word;
    EXPECT_EQ(moves[0].work_offset, c.offset) << c.word;
  }
  // A later selection holds from its block on.
  const auto two = read_program("G54\nG0 X1\nG56\nG0 X2\n", test::table_table_ac(), read_named("a.nc"));
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[0].work_offset, 1);
  EXPECT_EQ(two[1].work_offset, 3);
}

TEST(MachineProgramReader, RefusesAMalformedPresetCycle) {
  const MachineDefinition bc = test::head_table_bc();
  EXPECT_EQ(program_error_of("1 CYCL DEF 247 DATUM SETTING\n", bc), "prog.nc:1: column 3: CYCL DEF 247 without Q339 (the preset number)");
  EXPECT_EQ(program_error_of("1 CYCL DEF 247 DATUM SETTING ~\n  Q339=+1.5 ;DATUM NUMBER\n", bc),
            "prog.nc:2: column 3: expected a preset number >= 0 in Q339");
  EXPECT_EQ(program_error_of("1 CYCL DEF 247 DATUM SETTING ~\n  Q339=+1 ~\n  Q339=+2\n", bc),
            "prog.nc:3: column 3: Q339 is given twice");
  EXPECT_EQ(program_error_of("1 CYCL DEF 247 DATUM SETTING ~\n  Q305=+1 ;NUMBER IN TABLE\n", bc),
            "prog.nc:2: column 3: expected Q339=<preset number> in CYCL DEF 247 (its only parameter)");
  EXPECT_EQ(program_error_of("1 CYCL DEF 7.0 DATUM SHIFT\n", bc), "prog.nc:1: column 3: unsupported cycle: expected CYCL DEF 247 DATUM SETTING");
  EXPECT_EQ(program_error_of("1 CYCL DEF 247 DATUM SETTING ~", bc), "prog.nc:1: column 1: the block ends in '~' but no line follows");
  EXPECT_EQ(program_error_of("1 Q339=+1\n", bc), "prog.nc:1: column 3: parameter Q339 outside a cycle definition");
  // Fanuc's additional work offsets read as G54.1 P<n> (offset 6 + n, the
  // post's numbering), with P only there.
  EXPECT_EQ(program_error_of("G54.1\n", test::table_table_ac()),
            "prog.nc:1: column 1: G54.1 without P<n> (the additional work offset)");
  EXPECT_EQ(program_error_of("G54 P2\n", test::table_table_ac()), "prog.nc:1: column 1: a P word outside G54.1 P<n>");
  EXPECT_EQ(program_error_of("G54.1 P0\n", test::table_table_ac()), "prog.nc:1: column 7: expected P<n>, n >= 1 (G54.1 P<n>)");
  const auto moves = read_program("G54.1 P2\nG0 X1 Y0 Z0 A0 C0\n", test::table_table_ac(), ProgramReadOptions{});
  ASSERT_EQ(moves.size(), 1u);
  EXPECT_EQ(moves[0].work_offset, 8);
}

TEST(MachineProgramReader, ErrorsNameLineAndColumn) {
  const MachineDefinition ac = test::table_table_ac();
  EXPECT_EQ(program_error_of("G0 X0 Y0 Z0\nN10 G1 X10 Q5 F100\n", ac),
            "prog.nc:2: column 12: unsupported word 'Q'");
  EXPECT_EQ(program_error_of("G1 X1 B5 F10\n", ac), "prog.nc:1: column 7: machine 'test A/C trunnion' has no axis B");
  EXPECT_EQ(program_error_of("G2 X1 F10\n", ac), "prog.nc:1: column 1: arcs (G2/G3) are not supported");
  EXPECT_EQ(program_error_of("G91\n", ac), "prog.nc:1: column 1: incremental coordinates (G91) are not supported");
  EXPECT_EQ(program_error_of("G1 X1 (open\n", ac), "prog.nc:1: column 7: comment '(' is not closed");
  EXPECT_EQ(program_error_of("G1 X1\n", ac), "prog.nc:1: column 1: feed move without a feed (F)");
  EXPECT_EQ(program_error_of("X1\n", ac), "prog.nc:1: column 1: axis words before any G0/G1");
  EXPECT_EQ(program_error_of("G0 X1 RAPID\n", ac), "prog.nc:1: column 7: unknown word 'RAPID'");
  EXPECT_EQ(program_error_of("G0 X\n", ac), "prog.nc:1: column 4: unknown word 'X'");
  EXPECT_EQ(program_error_of("G0 X-\n", ac), "prog.nc:1: column 5: expected a number");
  EXPECT_EQ(program_error_of("G0 X1 G12.5\n", ac), "prog.nc:1: column 7: unsupported G code G12.5");
}

}  // namespace
}  // namespace bliskrun
