#pragma once
// Cutters as immutable values: a cutting part described by its meridian
// profile, plus a cylindrical shank and holder stacked above it on the axis.
//
// Tool frame: origin at the reference point, +z up the axis towards the
// shank. The reference point is the tip (lowest point on the axis) for every
// cutter except the belt-grinding contact wheel, whose reference is its
// centre. A pose (pose.h) places this frame in the part.
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "core/tools/profile.h"

namespace bliskrun {

enum class ToolKind { DrumWheel, ConicalDrumWheel, FlatEndMill, BallEndMill, TaperedBallEndMill, ContactWheel };
const char* to_string(ToolKind kind);

enum class ToolPartId { Cutter = 0, Shank = 1, Holder = 2 };
constexpr int kToolPartCount = 3;
const char* to_string(ToolPartId part);

// A plain cylinder on the axis; length 0 means "absent".
struct CylinderSpec {
  double diameter_mm = 0;
  double length_mm = 0;
};

// Symmetric drum (barrel) wheel, blisk paper Fig. 2 and Table 3: maximum
// diameter D_t at mid-height, barrel arc of radius R_c centred at L_c/2,
// head height L_c, then a shank of diameter d and length h.
struct DrumWheelSpec {
  double max_diameter_mm = 0;   // D_t
  double barrel_radius_mm = 0;  // R_c, at least D_t/2
  double head_length_mm = 0;    // L_c
  CylinderSpec shank;           // d, h
  CylinderSpec holder;
};

// Conical drum wheel: the barrel arc of radius R_c runs from the bottom
// diameter to the top diameter over the head height, bulging outwards; the
// widest point lies where the arc's centre height is, or at an end.
struct ConicalDrumWheelSpec {
  double bottom_diameter_mm = 0;
  double top_diameter_mm = 0;
  double barrel_radius_mm = 0;  // R_c, at least half the chord end to end
  double head_length_mm = 0;
  CylinderSpec shank;
  CylinderSpec holder;
};

// Flat-end (bull-nose) mill: radius R, corner radius r (0 = sharp, R = ball).
struct FlatEndMillSpec {
  double radius_mm = 0;
  double corner_radius_mm = 0;
  double flute_length_mm = 0;  // height of the cutting part, at least r
  CylinderSpec shank;
  CylinderSpec holder;
};

struct BallEndMillSpec {
  double radius_mm = 0;
  double flute_length_mm = 0;  // at least the radius
  CylinderSpec shank;
  CylinderSpec holder;
};

// Tapered ball end (impeller widening): ball of radius r at the tip, then a
// cone of half angle β tangent to it, widening up to the flute length.
struct TaperedBallEndMillSpec {
  double tip_radius_mm = 0;
  double half_angle_rad = 0;   // [0, pi/2)
  double flute_length_mm = 0;  // above the tangent circle
  CylinderSpec shank;
  CylinderSpec holder;
};

// Belt-grinding contact wheel (robot belt grinding): a disc of radius R and
// width W turning about the axis; reference point at its centre.
struct ContactWheelSpec {
  double radius_mm = 0;
  double width_mm = 0;
  CylinderSpec shank;  // the axle above the wheel, if it matters for clearance
  CylinderSpec holder;
};

class Tool {
 public:
  // Each factory throws ParameterError naming the parameter and why.
  static Tool drum_wheel(const DrumWheelSpec& spec);
  static Tool conical_drum_wheel(const ConicalDrumWheelSpec& spec);
  static Tool flat_end_mill(const FlatEndMillSpec& spec);
  static Tool ball_end_mill(const BallEndMillSpec& spec);
  static Tool tapered_ball_end_mill(const TaperedBallEndMillSpec& spec);
  static Tool contact_wheel(const ContactWheelSpec& spec);

  ToolKind kind() const { return kind_; }
  // "drum wheel D_t=8 R_c=50 L_c=4 shank d=6 h=96", for reports.
  const std::string& description() const { return description_; }

  bool has(ToolPartId part) const { return present_[static_cast<int>(part)]; }
  // Meridian profile of a part; throws ParameterError if it is absent.
  const Profile& profile(ToolPartId part) const;
  const Profile& cutter() const { return profile(ToolPartId::Cutter); }

  // R(z) of the whole tool: the widest part at height z; 0 off the tool.
  double radius_at(double z) const;
  // Signed distance to one part (exact, negative inside).
  double signed_distance(const Vec3& p_tool, ToolPartId part) const;
  // Signed distance to the whole tool: exact outside and on the surface;
  // inside, a lower bound of the depth (the deepest single part).
  double signed_distance(const Vec3& p_tool) const;
  // Largest distance of a tool point from the reference point.
  double reach() const;

  // The cutting part's effective radius and cut width (profile.h).
  double effective_radius(double z, double angle_from_meridian_rad) const {
    return cutter().effective_radius(z, angle_from_meridian_rad);
  }
  CutWidth cut_width(double z_contact, double k_surface_per_mm, double residual_height_mm) const {
    return cutter().cut_width(z_contact, k_surface_per_mm, residual_height_mm);
  }
  // Height of the side point a flank contact is planned at by default: the
  // widest point of a drum wheel (L_c/2 for the symmetric one), the middle of
  // the straight side of a mill or of the cone of a tapered ball end, the
  // centre plane of a contact wheel. Always inside (z_min, z_max).
  double flank_contact_height() const { return flank_contact_height_mm_; }

 private:
  Tool() = default;
  void set_part(ToolPartId part, Profile profile);
  // Adds shank and holder above the cutter; validates them.
  void stack_shank_and_holder(const CylinderSpec& shank, const CylinderSpec& holder);

  ToolKind kind_ = ToolKind::DrumWheel;
  std::string description_;
  std::array<Profile, kToolPartCount> profiles_;
  std::array<bool, kToolPartCount> present_{};
  double flank_contact_height_mm_ = 0;
};

}  // namespace bliskrun
