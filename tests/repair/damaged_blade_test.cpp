// The damaged built-in blade, its measurement files, the in-plane ICP and the
// rebuild of damaged sections (repair paper §1.4) against what the damage
// simulation knows: the deformed design is the true blade.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "core/common/error.h"
#include "core/parts/builtin_blisk.h"
#include "core/repair/damaged_blade.h"
#include "core/repair/damaged_rebuild.h"
#include "repair/builtin_design.h"

namespace bliskrun {
namespace {


// Distance from q to the closed polygon.
double polygon_distance(const Vec2& q, const std::vector<Vec2>& poly) {
  double best = 1e300;
  for (size_t j = 0; j < poly.size(); ++j) {
    const Vec2& a = poly[j];
    const Vec2& b = poly[(j + 1) % poly.size()];
    const double t = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + t * (b - a) - q).norm());
  }
  return best;
}

std::string parse_error_in(const std::string& text, const std::string& file) {
  try {
    parse_section_measurement(text, file);
  } catch (const DataError& e) {
    return e.what();
  }
  return "no error";
}

std::string parse_error(const std::string& text) {
  try {
    parse_section_measurement(text, "m.txt");
  } catch (const DataError& e) {
    return e.what();
  }
  return "no error";
}

TEST(DamagedBlade, MeasurementFileRoundTripsExactly) {
  BladeDamage dmg;
  dmg.tip = true;
  dmg.tip_span = 0.7;
  dmg.tip_tilt_rad = deg_to_rad(10);
  MeasurementOptions mo;
  mo.sections = 6;
  mo.points = 120;
  mo.face_points = 10;
  const SectionMeasurement m = measure_sections(DamagedBlade(test::builtin_blade_design(), dmg), mo);
  ASSERT_EQ(m.sections.size(), 4u);  // spans 0.03 .. 0.97 in 6: the break at 0.7 takes the top two
  ASSERT_EQ(m.face.size(), 10u);
  const SectionMeasurement r = parse_section_measurement(format_section_measurement(m), "x");
  ASSERT_EQ(r.sections.size(), m.sections.size());
  EXPECT_TRUE(r.has_frame);
  EXPECT_EQ(r.frame.origin, m.frame.origin);
  EXPECT_LT((r.frame.axis - m.frame.axis).norm(), 1e-15);
  for (size_t k = 0; k < m.sections.size(); ++k) {
    EXPECT_EQ(r.sections[k].index, m.sections[k].index);
    EXPECT_EQ(r.sections[k].height_mm, m.sections[k].height_mm);
    EXPECT_EQ(r.sections[k].points, m.sections[k].points);
  }
  EXPECT_EQ(r.face, m.face);
  // The plan's top (span 0.97) is stated although the probe found nothing there.
  EXPECT_EQ(m.planned_top_mm, test::builtin_blade_design().span_height(0.97));
  EXPECT_EQ(r.planned_top_mm, m.planned_top_mm);
}

TEST(DamagedBlade, ReaderNamesFileLineAndExpectation) {
  EXPECT_NE(parse_error("units mm\nsection 1 2.5\n1 2 3\n1 2\n").find("m.txt:4: expected 3 numbers (x y z of a point)"),
            std::string::npos);
  EXPECT_NE(parse_error("# c\n1 2 3\n").find("m.txt:2: expected 'section <number> <height>' or 'face'"),
            std::string::npos);
  EXPECT_NE(parse_error("units cm\n").find("m.txt:1: expected 'units mm' or 'units inch'"), std::string::npos);
  EXPECT_NE(parse_error("section 1 5\n1 2 3\nsection 2 4\n").find("m.txt:3: expected sections in increasing height"),
            std::string::npos);
  EXPECT_NE(parse_error("x,y,z\n1,2,3\n1,2\n").find("m.txt:3: expected 3 or 4 comma-separated numbers"),
            std::string::npos);
  EXPECT_NE(parse_error("1,2,3,1.5\n").find("m.txt:1: expected a whole section number"), std::string::npos);
  EXPECT_NE(parse_error("section 1 1\n1 2 abc\n").find("m.txt:2: expected a finite number (x y z of a point), got 'abc'"),
            std::string::npos);
  // A CMM export: grouped by the section column, heights from z, sorted; inch converted.
  const SectionMeasurement c = parse_section_measurement("X,Y,Z,SEC\n0,0,2,7\n1,0,1,3\n1,1,2,7\n", "c.csv");
  ASSERT_EQ(c.sections.size(), 2u);
  EXPECT_EQ(c.sections[0].index, 3);
  EXPECT_EQ(c.sections[0].height_mm, 1);
  EXPECT_EQ(c.sections[1].points.size(), 2u);
  const SectionMeasurement in = parse_section_measurement("units inch\nplanned_top 2\nsection 1 1\n1 0 1\n", "i");
  EXPECT_EQ(in.sections[0].points[0], Vec3(25.4, 0, 25.4));
  EXPECT_EQ(in.planned_top_mm, 50.8);
  EXPECT_NE(parse_error("planned_top 5\nplanned_top 6\n").find("m.txt:2: expected one 'planned_top' line"),
            std::string::npos);
  EXPECT_NE(parse_error("planned_top 5\nunits inch\n").find("m.txt:2: expected the units before"), std::string::npos);
}

TEST(DamagedBlade, CsvWithoutASectionColumnIsGroupedByZOnlyWhereThatHolds) {
  // Sections at constant Z (stacked along Z): grouped by Z.
  std::string flat = "x,y,z\n";
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 12; ++j) flat += std::to_string(j) + ",0," + std::to_string(5 * k) + "\n";
  const SectionMeasurement f = parse_section_measurement(flat, "flat.csv");
  ASSERT_EQ(f.sections.size(), 2u);
  EXPECT_EQ(f.sections[1].height_mm, 5);
  EXPECT_EQ(f.sections[1].line, 14);  // where its first point is
  // A radially stacked blade: each point at its own Z (issue 43: thousands
  // of one-point sections and a confusing error) is refused at the file's
  // first point, asking for the column.
  std::string radial = "x,y,z\n";
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 12; ++j) radial += std::to_string(5 * k) + ",0," + std::to_string(0.1 * j) + "\n";
  const std::string e = parse_error_in(radial, "radial.csv");
  EXPECT_NE(e.find("radial.csv:2: points without a section column are grouped by Z"), std::string::npos) << e;
  EXPECT_NE(e.find("add a 4th column"), std::string::npos) << e;
  // With the column it is read.
  std::string columns = "x,y,z,section\n";
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 12; ++j) columns += std::to_string(5 * k) + ",0," + std::to_string(0.1 * j) + "," + std::to_string(k + 1) + "\n";
  EXPECT_EQ(parse_section_measurement(columns, "c.csv").sections.size(), 2u);
  // Columns mixed: named at the line.
  EXPECT_NE(parse_error_in("1,2,3\n1,2,3,4\n", "m.csv").find("m.csv:2: expected 3 columns on every line"), std::string::npos);
}

TEST(DamagedBlade, AMeasurementErrorIsNamedAtTheDataFilesLine) {
  // A section too small to order is named at its line in the file, not only
  // by its number.
  std::string text = "units mm\n";
  for (int k = 0; k < 3; ++k) {
    const double h = test::builtin_blade_design().span_height(0.2 + 0.3 * k);
    const std::vector<Vec2> s = plane_section(test::builtin_blade_design().loft, test::builtin_blade_design().frame, h, k == 1 ? 4 * 16 : 400);
    text += "section " + std::to_string(k + 1) + " " + std::to_string(h) + "\n";
    const int step = k == 1 ? 16 : 1;  // section 2: 4 points
    for (size_t j = 0; j < s.size(); j += step) {
      const Vec3 p = test::builtin_blade_design().frame.point(h, s[j]);
      char line[128];
      std::snprintf(line, sizeof line, "%.9f %.9f %.9f\n", p.x(), p.y(), p.z());
      text += line;
    }
  }
  SectionMeasurement m = parse_section_measurement(text, "blade.txt");
  m.frame = test::builtin_blade_design().frame;
  m.has_frame = true;
  const int line = m.sections[1].line;
  EXPECT_EQ(line, 2 + 400 + 1);
  try {
    rebuild_damaged(m, test::builtin_blade_design());
    ADD_FAILURE() << "a 4-point section was rebuilt";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("blade.txt:" + std::to_string(line) + ": section 2"), std::string::npos) << e.what();
  }
}

TEST(DamagedBlade, IcpRecoversAKnownRigidMotionOfASection) {
  const DesignBlade& d = test::builtin_blade_design();
  const double h = d.span_height(0.5);
  const std::vector<Vec2> model = plane_section(d.loft, d.frame, h, 1024);
  // The measured section: the same blade sampled elsewhere (at other v),
  // moved, noisy, with a third of its profile (round the leading edge) missing.
  const Rigid2 truth{deg_to_rad(2.0), Vec2(0.3, -0.2)};
  const std::vector<Vec2> other = plane_section(d.loft, d.frame, h, 1500);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.002);
  std::vector<Vec2> measured;
  for (size_t j = 0; j < other.size(); ++j) {
    if (j > other.size() / 3 && j < other.size() * 2 / 3) continue;
    measured.push_back(truth.apply(other[j]) + Vec2(noise(rng), noise(rng)));
  }
  const SectionRegistration r = register_section(measured, model);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.motion.angle_rad, truth.angle_rad, 2e-5);  // 0.001 deg
  EXPECT_LT((r.motion.shift - truth.shift).norm(), 0.001);
  EXPECT_NEAR(r.rms_mm, 0.002, 0.0005);  // the noise, nothing of the model's shape
}

TEST(DamagedBlade, RebuiltEdgeDamagedSectionsAreTheDeformedDesign) {
  BladeDamage dmg;
  dmg.twist_rad = deg_to_rad(1.5);
  dmg.bend_mm = 0.3;
  dmg.edge = true;
  dmg.edge_from = 0.35;
  dmg.edge_to = 0.75;
  dmg.edge_depth_mm = 1.0;
  const DamagedBlade blade(test::builtin_blade_design(), dmg);
  MeasurementOptions mo;
  mo.sections = 12;
  mo.points = 1200;
  mo.noise_mm = 0.002;
  const SectionMeasurement m = measure_sections(blade, mo);
  const DamagedRebuild r = rebuild_damaged(m, test::builtin_blade_design());
  int completed = 0;
  double worst = 0;
  for (const DamagedSection& s : r.sections) {
    if (s.source != SectionSource::completed || s.gap_mm < 0.3) continue;  // the nick, not a stray's hole
    ++completed;
    // The truth where the nick took material, against the rebuilt section.
    const std::vector<Vec2> truth = blade.deformed_section(s.height_mm, 2048);
    const std::vector<Vec2> rebuilt = plane_section(r.loft, r.frame, s.height_mm, 2048);
    int inside = 0;
    for (const Vec2& q : truth)
      if (blade.removed(s.height_mm, q, truth)) {
        ++inside;
        worst = std::max(worst, polygon_distance(q, rebuilt));
      }
    EXPECT_GT(inside, 10);
    // The design was registered with the section's own motion (twist, bend).
    const Vec2 axis_point = blade.deform(s.height_mm, Vec2::Zero());
    EXPECT_LT((s.motion.apply(Vec2::Zero()) - axis_point).norm(), 0.002) << s.height_mm;
  }
  EXPECT_GE(completed, 3);
  // 3 sigma. Measured 4.7 um: the registration's error from the noise, the
  // smoothing's shrink of the 0.4 mm leading edge (L^4 / R^3 = 1.6 um at
  // L = 0.1 mm), the polygons' sagitta at the edge (0.5 um).
  EXPECT_LT(worst, 0.006);
  // The measured points lie on the rebuilt blade to the noise: mean |N(0, s)| = 0.80 s.
  EXPECT_GT(r.deviation.mean_mm, 0.6 * mo.noise_mm);
  EXPECT_LT(r.deviation.mean_mm, 1.0 * mo.noise_mm);
}

// Issue 43: the tip is extended only when the measurement shows material
// missing there. A fixed multiple of the section step read the ordinary
// margin above a dense plan's top section (3 % of span at 100 sections,
// more than 1.5 steps of 0.95 %) as a broken tip: a phantom region of
// ~58 mm3 on an intact blade.
TEST(DamagedBlade, ADensePlansMarginIsNotABrokenTip) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "60 sections rebuilt twice (~2 s in Release); the tip rule runs under the sanitizers in "
                  "ABreakIsToldFromThePlanOrTheMargins";
#endif
  BladeDamage dmg;
  dmg.twist_rad = deg_to_rad(1.0);
  MeasurementOptions mo;
  mo.sections = 60;  // 3 % of span above the top section, 1.6 % between sections
  mo.points = 240;
  mo.face_points = 0;
  SectionMeasurement m = measure_sections(DamagedBlade(test::builtin_blade_design(), dmg), mo);
  const double step = m.sections[1].height_mm - m.sections[0].height_mm;
  const double margin = test::builtin_blade_design().h_hi - m.sections.back().height_mm;
  ASSERT_GT(margin, 1.5 * step);  // the old rule's case
  const DamagedRebuild planned = rebuild_damaged(m, test::builtin_blade_design());
  EXPECT_FALSE(planned.tip_extended) << planned.tip_basis;
  EXPECT_NE(planned.tip_basis.find("is the plan's top"), std::string::npos) << planned.tip_basis;
  m.planned_top_mm = std::numeric_limits<double>::quiet_NaN();  // a file without the plan's top
  const DamagedRebuild by_margins = rebuild_damaged(m, test::builtin_blade_design());
  EXPECT_FALSE(by_margins.tip_extended) << by_margins.tip_basis;
  EXPECT_NE(by_margins.tip_basis.find("cannot be told from sections alone"), std::string::npos) << by_margins.tip_basis;
}

TEST(DamagedBlade, ABreakIsToldFromThePlanOrTheMargins) {
  BladeDamage dmg;
  dmg.tip = true;
  dmg.tip_span = 0.8;
  MeasurementOptions mo;
  mo.sections = 10;
  mo.points = 300;
  mo.face_points = 0;
  SectionMeasurement m = measure_sections(DamagedBlade(test::builtin_blade_design(), dmg), mo);
  ASSERT_EQ(m.sections.size(), 8u);  // spans 0.03 .. 0.97 in 10: the break at 0.8 takes the top two
  const DamagedRebuild planned = rebuild_damaged(m, test::builtin_blade_design());
  EXPECT_TRUE(planned.tip_extended);
  EXPECT_NE(planned.tip_basis.find("broken tip: the plan's top section"), std::string::npos) << planned.tip_basis;
  m.planned_top_mm = std::numeric_limits<double>::quiet_NaN();
  const DamagedRebuild by_margins = rebuild_damaged(m, test::builtin_blade_design());
  EXPECT_TRUE(by_margins.tip_extended);
  EXPECT_NE(by_margins.tip_basis.find("broken tip: "), std::string::npos) << by_margins.tip_basis;
  // The plan stated in the options when the file does not: a plan that
  // ended at the highest measured section makes the same blade intact.
  DamagedRebuildOptions o;
  o.planned_top_mm = m.sections.back().height_mm;
  const DamagedRebuild stated = rebuild_damaged(m, test::builtin_blade_design(), o);
  EXPECT_FALSE(stated.tip_extended);
  EXPECT_NE(stated.tip_basis.find("the options' planned_top"), std::string::npos) << stated.tip_basis;
}

TEST(DamagedBlade, RebuildOnTwoThreadsIsTheRebuildOnOne) {
  // Sections are ordered, smoothed and profiled, and points measured, on
  // the options' threads: the loft and every figure must be the same.
  BladeDamage dmg;
  dmg.twist_rad = deg_to_rad(1.5);
  dmg.edge = true;
  MeasurementOptions mo;
  mo.sections = 12;
  mo.points = 800;
  mo.outlier_fraction = 0.005;
  const SectionMeasurement m = measure_sections(DamagedBlade(test::builtin_blade_design(), dmg), mo);
  DamagedRebuildOptions one, two;
  two.rebuild.threads = 2;
  const DamagedRebuild a = rebuild_damaged(m, test::builtin_blade_design(), one);
  const DamagedRebuild b = rebuild_damaged(m, test::builtin_blade_design(), two);
  ASSERT_EQ(a.loft.grid.points.size(), b.loft.grid.points.size());
  for (size_t i = 0; i < a.loft.grid.points.size(); ++i) ASSERT_EQ(a.loft.grid.points[i], b.loft.grid.points[i]) << i;
  EXPECT_EQ(a.deviation.mean_mm, b.deviation.mean_mm);
  EXPECT_EQ(a.deviation.max_mm, b.deviation.max_mm);
  ASSERT_EQ(a.sections.size(), b.sections.size());
  for (size_t k = 0; k < a.sections.size(); ++k) {
    EXPECT_EQ(a.sections[k].kept, b.sections[k].kept);
    EXPECT_EQ(a.sections[k].start_correlation, b.sections[k].start_correlation);
  }
  // And an error names the same section whatever the thread count.
  SectionMeasurement bad = m;
  bad.sections[3].points.resize(5);
  bad.sections[9].points.resize(5);
  std::string one_says, two_says;
  try {
    rebuild_damaged(bad, test::builtin_blade_design(), one);
  } catch (const ParameterError& e) {
    one_says = e.what();
  }
  try {
    rebuild_damaged(bad, test::builtin_blade_design(), two);
  } catch (const ParameterError& e) {
    two_says = e.what();
  }
  EXPECT_FALSE(one_says.empty());
  EXPECT_EQ(one_says, two_says);
}

TEST(DamagedBlade, ADenseMeasurementIsThinnedOnTheWayInAndRebuiltAsASparseOne) {
#ifdef BLISKRUN_SANITIZED
  GTEST_SKIP() << "460 000 measured points through the rebuild (~4 s in the Release build)";
#endif
  // Issue 43: 10 million points did not rebuild in 7 minutes. Sections of
  // more than thin_above points are thinned to a quarter of the smoothing
  // length (25 um) first: here 10 sections of 40 000 points (2 um apart,
  // strays, a nick) come out ~2 500 measured points each, rebuilt trusted
  // and as close to them as a sparse measurement's.
  BladeDamage dmg;
  dmg.twist_rad = deg_to_rad(1.5);
  dmg.edge = true;
  const DamagedBlade blade(test::builtin_blade_design(), dmg);
  MeasurementOptions mo;
  mo.sections = 10;
  mo.points = 40000;
  const SectionMeasurement m = measure_sections(blade, mo);
  const DamagedRebuild r = rebuild_damaged(m, test::builtin_blade_design());
  ASSERT_TRUE(r.quality.trusted) << r.quality.message;
  for (const DamagedSection& s : r.sections) {
    EXPECT_GT(s.thinned, 30000) << s.height_mm;
    EXPECT_GT(s.kept, 1500) << s.height_mm;
    EXPECT_LT(s.kept + s.thinned + s.rejected, mo.points + 1) << s.height_mm;
  }
  EXPECT_LT(r.quality.between_max_mm, 0.010);
  // The kept points are measured ones: mean |N(0, s)| = 0.80 s from the blade.
  EXPECT_GT(r.deviation.mean_mm, 0.6 * mo.noise_mm);
  EXPECT_LT(r.deviation.mean_mm, 1.0 * mo.noise_mm);
  // Off: every point ordered.
  DamagedRebuildOptions all;
  all.rebuild.thin_above = 0;
  MeasurementOptions few = mo;
  few.sections = 3;
  few.points = 21000;
  const DamagedRebuild r_all = rebuild_damaged(measure_sections(blade, few), test::builtin_blade_design(), all);
  for (const DamagedSection& s : r_all.sections) EXPECT_EQ(s.thinned, 0);
}

TEST(DamagedBlade, BadDamageAndMeasurementOptionsAreNamed) {
  BladeDamage dmg;
  dmg.edge = true;
  dmg.edge_from = 0.6;
  dmg.edge_to = 0.5;
  try {
    DamagedBlade(test::builtin_blade_design(), dmg);
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.name(), "edge_to");
  }
  MeasurementOptions mo;
  mo.noise_mm = -1;
  EXPECT_THROW(measure_sections(DamagedBlade(test::builtin_blade_design(), BladeDamage{}), mo), ParameterError);
}

}  // namespace
}  // namespace bliskrun
