#include "core/io/camber_data.h"

#include <gtest/gtest.h>

#include <string>

#include "core/common/error.h"
#include "core/parts/impeller.h"  // builtin_impeller_definition

namespace bliskrun {
namespace {

// Four points a list; lines are counted in the comments.
std::string small_data(const std::string& hub_line_3 = "10 0 0 1") {
  return "# test data\n"            // 1
         "blades 5\n"               // 2
         "main shroud 4\n"          // 3
         "20 0 10 1\n"              // 4
         "21 1 10 1\n"              // 5
         "22 2 10 1\n"              // 6
         "23 3 10 1\n"              // 7
         "main hub 4\n"             // 8
         "8 -2 0 1\n"               // 9
         "9 -1 0 1\n"               // 10
         + hub_line_3 + "\n" +      // 11
         "11 1 0 1\n";              // 12
}

std::string camber_error_of(const std::string& text) {
  try {
    parse_camber_data(text, "camber.dat");
  } catch (const DataError& e) {
    return e.what();
  }
  return "no error";
}

TEST(CamberData, ReadsTheListsInOrder) {
  const ImpellerDefinition d = parse_camber_data(small_data(), "camber.dat");
  EXPECT_EQ(d.blade_count, 5);
  ASSERT_EQ(d.main.shroud.size(), 4u);
  ASSERT_EQ(d.main.hub.size(), 4u);
  EXPECT_EQ(d.main.shroud[1].p, Vec3(21, 1, 10));
  EXPECT_EQ(d.main.hub[2].p, Vec3(10, 0, 0));
  EXPECT_FALSE(d.splitter.has_value());
}

TEST(CamberData, BuiltinImpellerRoundTripsExactly) {
  const ImpellerDefinition d = builtin_impeller_definition();
  const ImpellerDefinition back = parse_camber_data(format_camber_data(d), "builtin");
  EXPECT_EQ(back.blade_count, d.blade_count);
  ASSERT_TRUE(back.splitter.has_value());
  EXPECT_EQ(back.splitter_offset_pitch, d.splitter_offset_pitch);
  ASSERT_EQ(back.main.hub.size(), d.main.hub.size());
  for (size_t i = 0; i < d.main.hub.size(); ++i) {
    EXPECT_EQ(back.main.hub[i].p, d.main.hub[i].p);
    EXPECT_EQ(back.main.hub[i].half_thickness_mm, d.main.hub[i].half_thickness_mm);
    EXPECT_EQ(back.splitter->shroud[i].p, d.splitter->shroud[i].p);
  }
}

TEST(CamberData, BadDataIsAnErrorAtFileAndLine) {
  EXPECT_EQ(camber_error_of("blades 5\nmain shroud 3\n1 0 0 1\n2 0 0 1\n3 0 0 1\n"),
            "camber.dat:2: main shroud: expected at least 4 camber points, got 3");
  EXPECT_EQ(camber_error_of(small_data("10 nan 0 1")),
            "camber.dat:11: expected a finite number (x y z h of main hub), got 'nan'");
  EXPECT_EQ(camber_error_of(small_data("10 0 0 0")),
            "camber.dat:11: main hub: expected a half thickness h > 0, got 0.000000");
  EXPECT_EQ(camber_error_of(small_data("8.5 -1.5 0 1")),
            "camber.dat:11: main hub: points must advance along the curve (leading edge -> "
            "trailing edge); this one turns back by 90 degrees or more");
  EXPECT_EQ(camber_error_of(small_data("9 -1 0 1")), "camber.dat:11: main hub: point repeats the previous point");
  EXPECT_EQ(camber_error_of(small_data("10 0 0")),
            "camber.dat:11: expected 4 numbers (x y z h of main hub), got 3 fields");
  EXPECT_EQ(camber_error_of("blades 5\nmain shroud 4\n1 0 0 1\n"),
            "camber.dat:4: unexpected end of file; expected main shroud point 2 of 4 (x y z h)");
  EXPECT_NE(camber_error_of("main hub 4\n8 -2 0 1\n9 -1 0 1\n10 0 0 1\n11 1 0 1\n").find("expected a 'blades N' line"),
            std::string::npos);
  // Hub and shroud of one blade pair point by point: unequal lists are
  // refused at the later list's header (line 8), whichever comes first.
  std::string five_hub = small_data();
  five_hub.replace(five_hub.find("main hub 4"), 10, "main hub 5");
  EXPECT_EQ(camber_error_of(five_hub + "12 2 0 1\n"),
            "camber.dat:8: expected as many points in 'main hub' as in 'main shroud' (4: point i of each "
            "lies on one ruling), got 5");
  EXPECT_EQ(camber_error_of(five_hub.substr(five_hub.find("main hub")) + "12 2 0 1\nblades 5\n" +
                     five_hub.substr(five_hub.find("main shroud"), five_hub.find("main hub") - five_hub.find("main shroud"))),
            "camber.dat:8: expected as many points in 'main shroud' as in 'main hub' (5: point i of each "
            "lies on one ruling), got 4");
  EXPECT_EQ(camber_error_of("blades 5\nwheel 4\n"),
            "camber.dat:2: expected 'blades N', 'splitter_offset F' or a list header "
            "'main|splitter shroud|hub <count>', got 'wheel 4'");
}

}  // namespace
}  // namespace bliskrun
