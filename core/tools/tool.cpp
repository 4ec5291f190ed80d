#include "core/tools/tool.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/common/error.h"
#include "core/common/fixed_text.h"

namespace bliskrun {
namespace {

using Kind = ProfileElement::Kind;

void require_positive(const char* name, double v, const char* what) {
  if (!std::isfinite(v) || !(v > 0)) {
    throw ParameterError(name, std::string(what) + " must be a positive length in mm, got " + short_text(v));
  }
}

void require_non_negative(const std::string& name, double v, const char* what) {
  if (!std::isfinite(v) || v < 0) {
    throw ParameterError(name, std::string(what) + " must be a non-negative length in mm, got " + short_text(v));
  }
}

// The solid of a cylinder of radius r between heights z0 and z1.
Profile cylinder_profile(double r, double z0, double z1) {
  return Profile({ProfileElement::segment({0, z0}, {r, z0}), ProfileElement::segment({r, z0}, {r, z1}),
                  ProfileElement::segment({r, z1}, {0, z1})});
}

std::string cylinder_text(const char* name, const CylinderSpec& c) {
  if (c.length_mm <= 0) return "";
  return std::string(" ") + name + " d=" + short_text(c.diameter_mm) + " h=" + short_text(c.length_mm);
}

}  // namespace

const char* to_string(ToolKind kind) {
  switch (kind) {
    case ToolKind::DrumWheel: return "drum wheel";
    case ToolKind::ConicalDrumWheel: return "conical drum wheel";
    case ToolKind::FlatEndMill: return "flat-end mill";
    case ToolKind::BallEndMill: return "ball-end mill";
    case ToolKind::TaperedBallEndMill: return "tapered ball-end mill";
    case ToolKind::ContactWheel: return "contact wheel";
  }
  return "tool";
}

const char* to_string(ToolPartId part) {
  switch (part) {
    case ToolPartId::Cutter: return "cutter";
    case ToolPartId::Shank: return "shank";
    case ToolPartId::Holder: return "holder";
  }
  return "part";
}

void Tool::set_part(ToolPartId part, Profile profile) {
  const int i = static_cast<int>(part);
  profiles_[i] = std::move(profile);
  present_[i] = true;
}

void Tool::stack_shank_and_holder(const CylinderSpec& shank, const CylinderSpec& holder) {
  double z = cutter().z_max();
  const std::pair<const char*, const CylinderSpec*> stack[] = {{"shank", &shank}, {"holder", &holder}};
  for (const auto& [name, spec] : stack) {
    require_non_negative(std::string(name) + ".diameter", spec->diameter_mm, "diameter");
    require_non_negative(std::string(name) + ".length", spec->length_mm, "length");
    if (spec->length_mm == 0) continue;
    if (spec->diameter_mm == 0) {
      throw ParameterError(std::string(name) + ".diameter",
                           "must be positive when the " + std::string(name) + " has a length");
    }
    const ToolPartId id = name == std::string("shank") ? ToolPartId::Shank : ToolPartId::Holder;
    set_part(id, cylinder_profile(spec->diameter_mm / 2, z, z + spec->length_mm));
    z += spec->length_mm;
  }
  description_ += cylinder_text("shank", shank) + cylinder_text("holder", holder);
}

const Profile& Tool::profile(ToolPartId part) const {
  if (!has(part)) throw ParameterError(to_string(part), std::string("this ") + to_string(kind_) + " has no " + to_string(part));
  return profiles_[static_cast<int>(part)];
}

double Tool::radius_at(double z) const {
  double r = 0;
  for (int i = 0; i < kToolPartCount; ++i) {
    if (present_[i]) r = std::max(r, profiles_[i].radius_at(z));
  }
  return r;
}

double Tool::signed_distance(const Vec3& p_tool, ToolPartId part) const {
  return profile(part).signed_distance(p_tool);
}

double Tool::signed_distance(const Vec3& p_tool) const {
  double d = cutter().signed_distance(p_tool);
  for (int i = 1; i < kToolPartCount; ++i) {
    if (present_[i]) d = std::min(d, profiles_[i].signed_distance(p_tool));
  }
  return d;
}

double Tool::reach() const {
  double r = 0;
  for (int i = 0; i < kToolPartCount; ++i) {
    if (present_[i]) r = std::max(r, profiles_[i].reach());
  }
  return r;
}

Tool Tool::drum_wheel(const DrumWheelSpec& s) {
  require_positive("max_diameter", s.max_diameter_mm, "D_t");
  require_positive("barrel_radius", s.barrel_radius_mm, "R_c");
  require_positive("head_length", s.head_length_mm, "L_c");
  const double rt = s.max_diameter_mm / 2, rc = s.barrel_radius_mm, half = s.head_length_mm / 2;
  if (rc < rt) {
    throw ParameterError("barrel_radius", "R_c = " + short_text(rc) + " mm is below D_t/2 = " + short_text(rt) +
                                              " mm: a barrel rounder than the wheel's own radius is not a drum "
                                              "wheel (use a ball or bull-nose tool)");
  }
  if (rc <= half) {
    throw ParameterError("barrel_radius", "R_c = " + short_text(rc) + " mm must exceed L_c/2 = " + short_text(half) +
                                              " mm so that the barrel arc spans the head height");
  }
  // Barrel arc centred at mid-height (paper Fig. 2), on the far side of the axis.
  const Vec2 centre(rt - rc, half);
  const double r_end = centre.x() + std::sqrt(rc * rc - half * half);
  if (!(r_end > 0)) {
    throw ParameterError("head_length", "L_c = " + short_text(s.head_length_mm) +
                                            " mm is too long for D_t and R_c: the barrel reaches the axis");
  }
  Tool t;
  t.kind_ = ToolKind::DrumWheel;
  t.description_ = "drum wheel D_t=" + short_text(s.max_diameter_mm) + " R_c=" + short_text(rc) + " L_c=" + short_text(s.head_length_mm);
  t.set_part(ToolPartId::Cutter,
             Profile({ProfileElement::segment({0, 0}, {r_end, 0}),
                      ProfileElement::arc(centre, rc, {r_end, 0}, {r_end, s.head_length_mm}),
                      ProfileElement::segment({r_end, s.head_length_mm}, {0, s.head_length_mm})}));
  t.flank_contact_height_mm_ = half;
  t.stack_shank_and_holder(s.shank, s.holder);
  return t;
}

Tool Tool::conical_drum_wheel(const ConicalDrumWheelSpec& s) {
  require_positive("bottom_diameter", s.bottom_diameter_mm, "bottom diameter");
  require_positive("top_diameter", s.top_diameter_mm, "top diameter");
  require_positive("barrel_radius", s.barrel_radius_mm, "R_c");
  require_positive("head_length", s.head_length_mm, "L_c");
  const Vec2 p0(s.bottom_diameter_mm / 2, 0), p1(s.top_diameter_mm / 2, s.head_length_mm);
  const double rc = s.barrel_radius_mm, half_chord = (p1 - p0).norm() / 2;
  if (rc <= half_chord) {
    throw ParameterError("barrel_radius", "R_c = " + short_text(rc) + " mm must exceed half the end-to-end chord " +
                                              short_text(half_chord) + " mm");
  }
  const Vec2 d = (p1 - p0).normalized(), towards_axis(-d.y(), d.x());
  const Vec2 centre = (p0 + p1) / 2 + std::sqrt(rc * rc - half_chord * half_chord) * towards_axis;
  if (p0.x() < centre.x() || p1.x() < centre.x()) {
    throw ParameterError("barrel_radius", "R_c = " + short_text(rc) +
                                              " mm is too small for the end diameters: the barrel would turn back "
                                              "towards the axis");
  }
  Tool t;
  t.kind_ = ToolKind::ConicalDrumWheel;
  t.description_ = "conical drum wheel D_bottom=" + short_text(s.bottom_diameter_mm) + " D_top=" + short_text(s.top_diameter_mm) +
                   " R_c=" + short_text(rc) + " L_c=" + short_text(s.head_length_mm);
  t.set_part(ToolPartId::Cutter,
             Profile({ProfileElement::segment({0, 0}, p0), ProfileElement::arc(centre, rc, p0, p1),
                      ProfileElement::segment(p1, {0, s.head_length_mm})}));
  // Widest where the arc is vertical (the centre's height), else at an end;
  // kept a little inside the open range so side_point() accepts it.
  const double margin = 1e-6 * s.head_length_mm;
  t.flank_contact_height_mm_ = std::clamp(centre.y(), margin, s.head_length_mm - margin);
  t.stack_shank_and_holder(s.shank, s.holder);
  return t;
}

namespace {

// Flat bottom, corner arc, straight side, flat top: flat-end, bull-nose and
// ball-end mills are all this chain.
Profile corner_radius_profile(double R, double r, double L) {
  std::vector<ProfileElement> e;
  if (R - r > 0) e.push_back(ProfileElement::segment({0, 0}, {R - r, 0}));
  if (r > 0) e.push_back(ProfileElement::arc({R - r, r}, r, {R - r, 0}, {R, r}));
  if (L > r) e.push_back(ProfileElement::segment({R, r}, {R, L}));
  e.push_back(ProfileElement::segment({R, L}, {0, L}));
  return Profile(std::move(e));
}

}  // namespace

Tool Tool::flat_end_mill(const FlatEndMillSpec& s) {
  require_positive("radius", s.radius_mm, "R");
  require_non_negative("corner_radius", s.corner_radius_mm, "r");
  require_positive("flute_length", s.flute_length_mm, "flute length");
  if (s.corner_radius_mm > s.radius_mm) {
    throw ParameterError("corner_radius", "r = " + short_text(s.corner_radius_mm) + " mm exceeds the tool radius R = " +
                                              short_text(s.radius_mm) + " mm");
  }
  if (s.flute_length_mm < s.corner_radius_mm) {
    throw ParameterError("flute_length", "must be at least the corner radius r = " + short_text(s.corner_radius_mm) + " mm");
  }
  Tool t;
  t.kind_ = ToolKind::FlatEndMill;
  t.description_ = "flat-end mill R=" + short_text(s.radius_mm) + " r=" + short_text(s.corner_radius_mm) +
                   " L=" + short_text(s.flute_length_mm);
  t.set_part(ToolPartId::Cutter, corner_radius_profile(s.radius_mm, s.corner_radius_mm, s.flute_length_mm));
  t.flank_contact_height_mm_ = (s.corner_radius_mm + s.flute_length_mm) / 2;
  t.stack_shank_and_holder(s.shank, s.holder);
  return t;
}

Tool Tool::ball_end_mill(const BallEndMillSpec& s) {
  require_positive("radius", s.radius_mm, "R");
  require_positive("flute_length", s.flute_length_mm, "flute length");
  if (s.flute_length_mm < s.radius_mm) {
    throw ParameterError("flute_length", "must be at least the ball radius R = " + short_text(s.radius_mm) + " mm");
  }
  Tool t;
  t.kind_ = ToolKind::BallEndMill;
  t.description_ = "ball-end mill R=" + short_text(s.radius_mm) + " L=" + short_text(s.flute_length_mm);
  t.set_part(ToolPartId::Cutter, corner_radius_profile(s.radius_mm, s.radius_mm, s.flute_length_mm));
  t.flank_contact_height_mm_ = (s.radius_mm + s.flute_length_mm) / 2;
  t.stack_shank_and_holder(s.shank, s.holder);
  return t;
}

Tool Tool::tapered_ball_end_mill(const TaperedBallEndMillSpec& s) {
  require_positive("tip_radius", s.tip_radius_mm, "tip ball radius");
  require_positive("flute_length", s.flute_length_mm, "flute length");
  if (!std::isfinite(s.half_angle_rad) || s.half_angle_rad < 0 || s.half_angle_rad >= kPi / 2) {
    throw ParameterError("half_angle", "taper half angle must lie in [0, 90) degrees");
  }
  const double rb = s.tip_radius_mm, beta = s.half_angle_rad;
  // The cone touches the ball where the ball's normal is perpendicular to the
  // cone's generator (sin β, cos β).
  const Vec2 tangent(rb * std::cos(beta), rb * (1 - std::sin(beta)));
  if (s.flute_length_mm <= tangent.y()) {
    throw ParameterError("flute_length", "must exceed the height of the ball-cone tangent circle, " +
                                             short_text(tangent.y()) + " mm");
  }
  const double r_top = tangent.x() + (s.flute_length_mm - tangent.y()) * std::tan(beta);
  Tool t;
  t.kind_ = ToolKind::TaperedBallEndMill;
  t.description_ = "tapered ball-end mill r=" + short_text(rb) + " half_angle=" + short_text(rad_to_deg(beta)) +
                   "deg L=" + short_text(s.flute_length_mm);
  t.set_part(ToolPartId::Cutter,
             Profile({ProfileElement::arc({0, rb}, rb, {0, 0}, tangent),
                      ProfileElement::segment(tangent, {r_top, s.flute_length_mm}),
                      ProfileElement::segment({r_top, s.flute_length_mm}, {0, s.flute_length_mm})}));
  t.flank_contact_height_mm_ = (tangent.y() + s.flute_length_mm) / 2;
  t.stack_shank_and_holder(s.shank, s.holder);
  return t;
}

Tool Tool::contact_wheel(const ContactWheelSpec& s) {
  require_positive("radius", s.radius_mm, "wheel radius");
  require_positive("width", s.width_mm, "wheel width");
  Tool t;
  t.kind_ = ToolKind::ContactWheel;
  t.description_ = "contact wheel R=" + short_text(s.radius_mm) + " W=" + short_text(s.width_mm);
  t.set_part(ToolPartId::Cutter, cylinder_profile(s.radius_mm, -s.width_mm / 2, s.width_mm / 2));
  t.flank_contact_height_mm_ = 0;
  t.stack_shank_and_holder(s.shank, s.holder);
  return t;
}

}  // namespace bliskrun
