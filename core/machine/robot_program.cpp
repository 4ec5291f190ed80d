#include "core/machine/robot_program.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

#include "core/common/error.h"

namespace bliskrun {

namespace {

struct Where {
  std::string file;
  int line = 0;
  std::string str() const { return (file.empty() ? "robot program" : file) + " line " + std::to_string(line); }
};

[[noreturn]] void fail(const Where& w, const std::string& what) { throw Error(w.str() + ": " + what); }

std::string trimmed(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

bool starts_with_word(const std::string& s, const std::string& word) {
  return s.size() > word.size() && s.compare(0, word.size(), word) == 0 &&
         (s[word.size()] == ' ' || s[word.size()] == '\t' || s[word.size()] == '{' || s[word.size()] == '[');
}

bool is_identifier(const std::string& s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

// The numbers of a bracketed RAPID aggregate, in order ([[1,2],[3]] -> 1 2 3).
std::vector<double> numbers_in(const std::string& s, const Where& w) {
  std::vector<double> out;
  const char* p = s.c_str();
  while (*p) {
    const bool starts = std::isdigit(static_cast<unsigned char>(*p)) ||
                        ((*p == '-' || *p == '+' || *p == '.') && std::isdigit(static_cast<unsigned char>(p[1]))) ||
                        ((*p == '-' || *p == '+') && p[1] == '.');
    if (starts) {
      char* end = nullptr;
      const double v = std::strtod(p, &end);
      if (end == p) fail(w, "unreadable number near '" + std::string(p).substr(0, 12) + "'");
      if (!std::isfinite(v)) fail(w, "non-finite number");
      out.push_back(v);
      p = end;
    } else {
      ++p;
    }
  }
  return out;
}

// The first balanced [...] in s from `from`, or "".
std::string bracketed(const std::string& s, size_t from) {
  const size_t a = s.find('[', from);
  if (a == std::string::npos) return "";
  int depth = 0;
  for (size_t i = a; i < s.size(); ++i) {
    if (s[i] == '[') ++depth;
    if (s[i] == ']' && --depth == 0) return s.substr(a, i - a + 1);
  }
  return "";
}

// Top-level comma-separated parts (outside [] and "").
std::vector<std::string> split_args(const std::string& s) {
  std::vector<std::string> out;
  int depth = 0;
  bool quoted = false;
  std::string cur;
  for (char c : s) {
    if (c == '"') quoted = !quoted;
    if (!quoted && c == '[') ++depth;
    if (!quoted && c == ']') --depth;
    if (!quoted && depth == 0 && c == ',') {
      out.push_back(trimmed(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!trimmed(cur).empty()) out.push_back(trimmed(cur));
  return out;
}

Frame pose_from(const double* v, const Where& w) {  // x y z qw qx qy qz
  Eigen::Quaterniond q(v[3], v[4], v[5], v[6]);
  if (std::abs(q.norm() - 1) > 1e-4) fail(w, "the orientation quaternion is not of unit length");
  Frame f = Frame::Identity();
  f.linear() = q.normalized().toRotationMatrix();
  f.translation() = Vec3(v[0], v[1], v[2]);
  return f;
}

bool rapid_bool(const std::string& s, const Where& w) {
  const std::string u = upper(trimmed(s));
  if (u == "TRUE") return true;
  if (u == "FALSE") return false;
  fail(w, "expected TRUE or FALSE, got '" + s + "'");
}

struct RapidTool {
  bool robhold = true;
  Frame frame = Frame::Identity();
  MassProperties tload;  // wrist (tool0) frame
};
struct RapidWobj {
  bool robhold = false;
  Frame frame = Frame::Identity();  // uframe · oframe
};
struct RapidSpeed {
  double tcp = 0, ori = 0;
};

// The state a controller keeps across a program and the programs it calls.
struct ReadState {
  const std::map<std::string, std::string>* programs = nullptr;
  RobotDialect dialect = RobotDialect::AbbRapid;
  std::vector<RobotTarget> out;
  std::vector<std::string> stack;  // programs being read (recursion guard)
  // RAPID: data by name (PERS data is one object per name in a task).
  std::map<std::string, RapidTool> tools;
  std::map<std::string, RapidWobj> wobjs;
  std::map<std::string, RapidSpeed> speeds;
  std::map<std::string, RobotTarget> robtargets;
  std::map<std::string, JointAngles> jointtargets;
  std::map<std::string, MassProperties> loads;  // loaddata by name
  MassProperties payload;                       // set by GripLoad; load0 (nothing) at the start
  std::map<std::string, std::string> pers_values;  // name -> its declaration's value text
  std::map<std::string, std::string> procs;        // PROC name -> module it is in
  // KRL: the system variables in force.
  Frame krl_tool = Frame::Identity(), krl_base = Frame::Identity();
  bool krl_tool_set = false, krl_base_set = false, krl_external = false;
  double krl_vel_cp_mm_s = 0, krl_ori1 = 0, krl_ori2 = 0;
  bool krl_load_set = false;
  MassProperties krl_load;  // $LOAD, flange frame
};

// A principal-axes description (moments in kg·m² about axes turned by `axes`
// from the frame) as an inertia tensor in that frame, kg·mm².
Mat3 inertia_from_principal(const Mat3& axes, const Vec3& moments_kg_m2) {
  return axes * (1e6 * moments_kg_m2).asDiagonal() * axes.transpose();
}

// RAPID loaddata [mass, [x, y, z], [q1, q2, q3, q4], ix, iy, iz].
MassProperties rapid_load(const std::string& aggregate, const Where& w) {
  const std::vector<double> v = numbers_in(aggregate, w);
  if (v.size() != 11) fail(w, "expected loaddata [mass, [x, y, z], [q1, q2, q3, q4], ix, iy, iz]");
  if (v[0] < 0) fail(w, "a load's mass must not be negative");
  Eigen::Quaterniond q(v[4], v[5], v[6], v[7]);
  if (std::abs(q.norm() - 1) > 1e-4) fail(w, "the load's axes of moment (aom) are not a unit quaternion");
  MassProperties m;
  m.mass_kg = v[0];
  m.cog_mm = Vec3(v[1], v[2], v[3]);
  m.inertia_kg_mm2 = inertia_from_principal(q.normalized().toRotationMatrix(), Vec3(v[8], v[9], v[10]));
  return m;
}

RobotTarget rapid_robtarget(const std::string& aggregate, const Where& w) {
  const std::vector<double> v = numbers_in(aggregate, w);
  if (v.size() != 17) fail(w, "expected a robtarget of 17 numbers, got " + std::to_string(v.size()));
  RobotTarget t;
  t.target = pose_from(v.data(), w);
  t.quadrants = {static_cast<int>(v[7]), static_cast<int>(v[8]), static_cast<int>(v[9])};
  t.cfx = static_cast<int>(v[10]);
  if (t.cfx < 0 || t.cfx > 7) fail(w, "cfx must be 0..7");
  return t;
}

RapidSpeed rapid_speed(ReadState& st, const std::string& arg, const Where& w) {
  if (!arg.empty() && arg[0] == '[') {
    const std::vector<double> v = numbers_in(arg, w);
    if (v.size() != 4) fail(w, "expected speeddata [v_tcp, v_ori, v_leax, v_reax]");
    return {v[0], v[1]};
  }
  if (const auto it = st.speeds.find(arg); it != st.speeds.end()) return it->second;
  // The predefined v5 .. v7000: v_ori 500 deg/s (RAPID reference, speeddata).
  if (arg.size() > 1 && arg[0] == 'v' && std::all_of(arg.begin() + 1, arg.end(), ::isdigit))
    return {std::atof(arg.c_str() + 1), 500};
  fail(w, "unknown speeddata '" + arg + "'");
}

void read_program(ReadState& st, const std::string& name, const std::string& text);

void read_rapid_line(ReadState& st, const std::string& s, const Where& w) {
  // Data declarations: [LOCAL] PERS|CONST|VAR type name := value;
  {
    std::istringstream words(s);
    std::string a, type, name;
    words >> a;
    if (a == "LOCAL" || a == "TASK") words >> a;
    if (a == "PERS" || a == "CONST" || a == "VAR") {
      words >> type >> name;
      const size_t assign = s.find(":=");
      if (assign == std::string::npos) return;  // declared without a value
      if (name.find(":=") != std::string::npos) name = name.substr(0, name.find(":="));
      const std::string value = trimmed(s.substr(assign + 2, s.rfind(';') == std::string::npos
                                                                   ? std::string::npos
                                                                   : s.rfind(';') - assign - 2));
      if (a == "PERS") {
        const auto [it, fresh] = st.pers_values.emplace(name, value);
        if (!fresh && it->second != value)
          fail(w, "PERS " + name + " is declared again with another value; RAPID keeps one object per PERS name in a "
                  "task, so one of the two programs would run with the other's data");
      }
      if (type == "tooldata") {
        const std::vector<std::string> f = split_args(value.substr(1, value.size() - 2));
        if (f.size() != 3) fail(w, "expected tooldata [robhold, tframe, tload]");
        const std::vector<double> v = numbers_in(f[1], w);
        if (v.size() != 7) fail(w, "expected tframe [[x,y,z],[q1,q2,q3,q4]]");
        st.tools[name] = {rapid_bool(f[0], w), pose_from(v.data(), w), rapid_load(f[2], w)};
      } else if (type == "wobjdata") {
        const std::vector<std::string> f = split_args(value.substr(1, value.size() - 2));
        if (f.size() != 5) fail(w, "expected wobjdata [robhold, ufprog, ufmec, uframe, oframe]");
        const std::vector<double> u = numbers_in(f[3], w), o = numbers_in(f[4], w);
        if (u.size() != 7 || o.size() != 7) fail(w, "expected uframe and oframe [[x,y,z],[q1,q2,q3,q4]]");
        st.wobjs[name] = {rapid_bool(f[0], w), pose_from(u.data(), w) * pose_from(o.data(), w)};
      } else if (type == "loaddata") {
        st.loads[name] = rapid_load(value, w);
      } else if (type == "speeddata") {
        st.speeds[name] = rapid_speed(st, value, w);
      } else if (type == "robtarget") {
        st.robtargets[name] = rapid_robtarget(bracketed(value, 0), w);
      } else if (type == "jointtarget") {
        const std::vector<double> v = numbers_in(value, w);
        if (v.size() != 12) fail(w, "expected a jointtarget of 12 numbers");
        JointAngles q;
        for (int i = 0; i < 6; ++i) q[i] = deg_to_rad(v[i]);
        st.jointtargets[name] = q;
      }
      return;
    }
  }
  if (starts_with_word(s, "GripLoad")) {
    // GripLoad load; — the payload the robot holds from here on.
    const std::string name = trimmed(s.substr(8, s.rfind(';') - 8));
    if (name == "load0") {
      st.payload = MassProperties();
      return;
    }
    const auto it = st.loads.find(name);
    if (it == st.loads.end()) fail(w, "unknown loaddata '" + name + "'");
    st.payload = it->second;
    return;
  }
  const bool move_l = starts_with_word(s, "MoveL"), move_j = starts_with_word(s, "MoveJ"),
             move_abs = starts_with_word(s, "MoveAbsJ");
  if (!move_l && !move_j && !move_abs) {
    // A call of another program's procedure: `name;`.
    const std::string call = trimmed(s.substr(0, s.find(';')));
    if (s.back() == ';' && is_identifier(call) && st.programs) {
      const auto it = st.procs.find(call);
      if (it != st.procs.end() && st.programs->count(it->second)) read_program(st, it->second, st.programs->at(it->second));
      else if (st.programs->count(call)) read_program(st, call, st.programs->at(call));
    }
    return;
  }
  const std::string body = trimmed(s.substr(move_abs ? 8 : 5, s.rfind(';') - (move_abs ? 8 : 5)));
  const std::vector<std::string> args = split_args(body);
  if (args.size() < 4) fail(w, "expected target, speed, zone and tool");
  RobotTarget t;
  t.line = w.line;
  t.file = w.file;
  if (move_abs) {
    t.axis_move = true;
    if (args[0][0] == '[') {
      const std::vector<double> v = numbers_in(args[0], w);
      if (v.size() != 12) fail(w, "expected a jointtarget of 12 numbers");
      for (int i = 0; i < 6; ++i) t.joints[i] = deg_to_rad(v[i]);
    } else {
      const auto it = st.jointtargets.find(args[0]);
      if (it == st.jointtargets.end()) fail(w, "unknown jointtarget '" + args[0] + "'");
      t.joints = it->second;
    }
    st.out.push_back(t);
    return;
  }
  if (args[0][0] == '[') {
    t = rapid_robtarget(args[0], w);
  } else {
    const auto it = st.robtargets.find(args[0]);
    if (it == st.robtargets.end()) fail(w, "unknown robtarget '" + args[0] + "'");
    t = it->second;
  }
  t.line = w.line;
  t.file = w.file;
  t.linear = move_l;
  const RapidSpeed sp = rapid_speed(st, args[1], w);
  t.tcp_speed_mm_s = sp.tcp;
  t.ori_speed_deg_s = sp.ori;
  const std::string tool_arg = args[3];
  const std::string tool_name = trimmed(tool_arg.substr(0, tool_arg.find('\\')));
  std::string wobj_name;
  if (const size_t at = tool_arg.find("\\WObj:="); at != std::string::npos) wobj_name = trimmed(tool_arg.substr(at + 7));
  const auto tool = st.tools.find(tool_name);
  if (tool == st.tools.end()) fail(w, "unknown tooldata '" + tool_name + "'");
  RapidWobj wobj;  // wobj0: the world, fixed
  if (!wobj_name.empty()) {
    const auto it = st.wobjs.find(wobj_name);
    if (it == st.wobjs.end()) fail(w, "unknown wobjdata '" + wobj_name + "'");
    wobj = it->second;
  }
  if (tool->second.robhold == wobj.robhold)
    fail(w, std::string("tool ") + tool_name + " and work object " + (wobj_name.empty() ? "wobj0" : wobj_name) +
                " are both " + (wobj.robhold ? "held by the robot" : "stationary") +
                " (robhold); one must be on the flange and the other in the world");
  t.external_tcp = !tool->second.robhold;
  t.fixed = t.external_tcp ? tool->second.frame : wobj.frame;
  t.held = t.external_tcp ? wobj.frame : tool->second.frame;
  // The load on the flange: the tool's tload (wrist frame) and the payload,
  // in the tool frame of a held tool or the object frame of a held work
  // object — both frames given on the flange.
  t.load_known = true;
  t.load = combined(tool->second.tload, transformed(st.payload, t.held));
  st.out.push_back(t);
}

// KRL's S and T: a decimal integer or 'B0101' binary.
int krl_bits(const std::string& s, const Where& w) {
  const std::string v = trimmed(s);
  if (v.size() > 2 && v[0] == '\'' && (v[1] == 'B' || v[1] == 'b')) {
    int bits = 0;
    for (size_t i = 2; i < v.size() && v[i] != '\''; ++i) {
      if (v[i] != '0' && v[i] != '1') fail(w, "bad binary status '" + v + "'");
      bits = bits * 2 + (v[i] - '0');
    }
    return bits;
  }
  char* end = nullptr;
  const long n = std::strtol(v.c_str(), &end, 10);
  if (end == v.c_str()) fail(w, "bad status or turn '" + v + "'");
  return static_cast<int>(n);
}

// The fields of a KRL aggregate {TYPE: NAME value, ...}.
std::map<std::string, std::string> krl_fields(const std::string& s, const Where& w) {
  const size_t a = s.find('{'), b = s.rfind('}');
  if (a == std::string::npos || b == std::string::npos || b < a) fail(w, "expected an aggregate {X .., ...}");
  std::string body = s.substr(a + 1, b - a - 1);
  if (const size_t colon = body.find(':'); colon != std::string::npos) body = body.substr(colon + 1);
  std::map<std::string, std::string> fields;
  std::istringstream parts(body);
  std::string part;
  while (std::getline(parts, part, ',')) {
    part = trimmed(part);
    const size_t sp = part.find(' ');
    if (sp == std::string::npos) fail(w, "expected 'NAME value' in '" + part + "'");
    fields[upper(part.substr(0, sp))] = trimmed(part.substr(sp + 1));
  }
  return fields;
}

double krl_number(const std::map<std::string, std::string>& f, const std::string& key, const Where& w) {
  const auto it = f.find(key);
  if (it == f.end()) fail(w, "missing " + key);
  char* end = nullptr;
  const double v = std::strtod(it->second.c_str(), &end);
  if (end == it->second.c_str() || !std::isfinite(v)) fail(w, "bad " + key);
  return v;
}

Frame krl_frame(const std::map<std::string, std::string>& f, const Where& w) {
  double v[6];
  const char* keys[6] = {"X", "Y", "Z", "A", "B", "C"};
  for (int i = 0; i < 6; ++i) v[i] = krl_number(f, keys[i], w);
  Frame t = Frame::Identity();
  t.linear() = (Eigen::AngleAxisd(deg_to_rad(v[3]), Vec3::UnitZ()) * Eigen::AngleAxisd(deg_to_rad(v[4]), Vec3::UnitY()) *
                Eigen::AngleAxisd(deg_to_rad(v[5]), Vec3::UnitX()))
                   .toRotationMatrix();
  t.translation() = Vec3(v[0], v[1], v[2]);
  return t;
}

// $LOAD = {M m, CM {X, Y, Z, A, B, C}, J {X, Y, Z}}: mass, centre of gravity
// and principal axes in FLANGE, principal moments in kg·m².
MassProperties krl_load(const std::string& s, const Where& w) {
  const std::string u = upper(s);
  auto inner = [&](const char* key) {
    size_t at = u.find(key);
    while (at != std::string::npos && at > 0 && std::isalnum(static_cast<unsigned char>(u[at - 1])))
      at = u.find(key, at + 1);
    if (at == std::string::npos) fail(w, std::string("$LOAD: missing ") + key);
    const size_t a = s.find('{', at), b = s.find('}', at);
    if (a == std::string::npos || b == std::string::npos || b < a) fail(w, std::string("$LOAD: expected ") + key + " {..}");
    return krl_fields("{" + s.substr(a + 1, b - a - 1) + "}", w);
  };
  const size_t m_at = u.find("{M ");
  if (m_at == std::string::npos) fail(w, "$LOAD: missing M");
  char* end = nullptr;
  const double mass = std::strtod(s.c_str() + m_at + 3, &end);
  if (end == s.c_str() + m_at + 3 || !std::isfinite(mass) || mass < 0) fail(w, "$LOAD: bad M");
  const Frame cm = krl_frame(inner("CM "), w);
  const auto j = inner("J ");
  MassProperties m;
  m.mass_kg = mass;
  m.cog_mm = cm.translation();
  m.inertia_kg_mm2 = inertia_from_principal(cm.linear(), Vec3(krl_number(j, "X", w), krl_number(j, "Y", w),
                                                              krl_number(j, "Z", w)));
  return m;
}

double krl_value(const std::string& s, const Where& w) {
  const std::string v = trimmed(s.substr(s.find('=') + 1));
  char* end = nullptr;
  const double x = std::strtod(v.c_str(), &end);
  if (end == v.c_str() || !std::isfinite(x)) fail(w, "expected a number in '" + s + "'");
  return x;
}

void read_krl_line(ReadState& st, const std::string& s, const Where& w) {
  const std::string u = upper(s);
  auto assigns = [&](const char* var) {
    const std::string v(var);
    return u.rfind(v, 0) == 0 && trimmed(u.substr(v.size())).rfind('=', 0) == 0;
  };
  if (assigns("$TOOL")) {
    st.krl_tool = krl_frame(krl_fields(s, w), w);
    st.krl_tool_set = true;
    return;
  }
  if (assigns("$BASE")) {
    st.krl_base = krl_frame(krl_fields(s, w), w);
    st.krl_base_set = true;
    return;
  }
  if (assigns("$IPO_MODE")) {
    const std::string v = trimmed(u.substr(u.find('=') + 1));
    if (v != "#TCP" && v != "#BASE") fail(w, "expected $IPO_MODE = #TCP or #BASE");
    st.krl_external = v == "#TCP";
    return;
  }
  if (assigns("$LOAD")) {
    st.krl_load = krl_load(s, w);
    st.krl_load_set = true;
    return;
  }
  if (assigns("$VEL.CP")) st.krl_vel_cp_mm_s = 1000 * krl_value(s, w);
  if (assigns("$VEL.ORI1")) st.krl_ori1 = krl_value(s, w);
  if (assigns("$VEL.ORI2")) st.krl_ori2 = krl_value(s, w);
  const bool lin = starts_with_word(u, "LIN"), ptp = starts_with_word(u, "PTP");
  if (!lin && !ptp) {
    // A call of another program: `name()`.
    const std::string call = trimmed(s);
    if (call.size() > 2 && call.compare(call.size() - 2, 2, "()") == 0 && st.programs) {
      const std::string name = trimmed(call.substr(0, call.size() - 2));
      for (const auto& [key, text] : *st.programs)
        if (upper(key) == upper(name)) read_program(st, key, text);
    }
    return;
  }
  const auto fields = krl_fields(s, w);
  RobotTarget t;
  t.line = w.line;
  t.file = w.file;
  t.linear = lin;
  if (fields.count("A1")) {
    if (lin) fail(w, "LIN to an axis position");
    t.axis_move = true;
    for (int i = 0; i < 6; ++i) t.joints[i] = deg_to_rad(krl_number(fields, "A" + std::to_string(i + 1), w));
    st.out.push_back(t);
    return;
  }
  t.target = krl_frame(fields, w);
  if (!fields.count("S") || !fields.count("T")) fail(w, "missing S or T (the configuration is part of the target)");
  t.cfx = krl_bits(fields.at("S"), w);
  t.turn_bits = krl_bits(fields.at("T"), w);
  if (!st.krl_tool_set || !st.krl_base_set) fail(w, "a Cartesian target before $TOOL and $BASE are set");
  t.external_tcp = st.krl_external;
  // #TCP: $BASE is the fixed tool in WORLD, $TOOL the workpiece on FLANGE;
  // #BASE: $BASE the workpiece in WORLD, $TOOL the tool on FLANGE. Either
  // way $BASE is in the world and $TOOL on the flange.
  t.fixed = st.krl_base;
  t.held = st.krl_tool;
  t.tcp_speed_mm_s = st.krl_vel_cp_mm_s;
  t.ori_speed_deg_s = std::min(st.krl_ori1, st.krl_ori2);
  t.load_known = st.krl_load_set;
  t.load = st.krl_load;
  st.out.push_back(t);
}

void read_program(ReadState& st, const std::string& name, const std::string& text) {
  if (std::find(st.stack.begin(), st.stack.end(), name) != st.stack.end())
    throw Error(name + ": called while it runs (recursion)");
  st.stack.push_back(name);
  if (st.dialect == RobotDialect::KukaKrl && st.programs) {
    // KSS selects a program by its file name: DEF must name the file.
    std::istringstream in(text);
    std::string raw, first;
    while (first.empty() && std::getline(in, raw)) {
      const std::string s = trimmed(raw.substr(0, raw.find(';')));
      if (!s.empty() && s[0] != '&') first = s;
    }
    const std::string expected = "DEF " + upper(name) + "(";
    if (upper(first).rfind(expected, 0) != 0)
      throw Error(name + ": the program's DEF line '" + first + "' does not name its file " + name);
  }
  std::istringstream in(text);
  std::string raw;
  int line = 0;
  while (std::getline(in, raw)) {
    ++line;
    const Where w{name, line};
    if (st.dialect == RobotDialect::AbbRapid) {
      const std::string s = trimmed(raw.substr(0, raw.find('!')));
      if (s.empty()) continue;
      read_rapid_line(st, s, w);
    } else {
      const std::string s = trimmed(raw.substr(0, raw.find(';')));
      if (s.empty() || s[0] == '&') continue;
      read_krl_line(st, s, w);
    }
  }
  st.stack.pop_back();
}

// RAPID: every PROC of every module, so that calls find their module and a
// name declared twice (two `PROC main`) is refused.
void index_procs(ReadState& st) {
  for (const auto& [module, text] : *st.programs) {
    std::istringstream in(text);
    std::string raw;
    int line = 0;
    while (std::getline(in, raw)) {
      ++line;
      const std::string s = trimmed(raw.substr(0, raw.find('!')));
      std::istringstream words(s);
      std::string a, name;
      words >> a;
      if (a == "LOCAL") words >> a;
      if (a != "PROC") continue;
      std::getline(words, name);
      name = trimmed(name.substr(0, name.find('(')));
      const auto [it, fresh] = st.procs.emplace(name, module);
      if (!fresh)
        fail({module, line}, "PROC " + name + " is also declared in " + it->second +
                                 "; a task cannot load two routines of one name");
    }
  }
}

double rotation_angle_deg(const Mat3& a, const Mat3& b) {
  return rad_to_deg(Eigen::AngleAxisd(a.transpose() * b).angle());
}

// A joint within 1e-3 rad (0.06°) of a boundary of its field — a quadrant's
// edge, or zero for a turn bit — reads either side: the post writes the
// field from the planned joints, and a target rounded to its written
// decimals may solve a hair across the edge.
constexpr double kSlack = 1e-3;

bool quadrants_match(const RobotTarget& t, const JointAngles& q) {
  const int joint[3] = {0, 3, 5};
  for (int i = 0; i < 3; ++i) {
    JointAngles lo = q, hi = q;
    lo[joint[i]] -= kSlack;
    hi[joint[i]] += kSlack;
    if (abb_quadrants(lo)[i] != t.quadrants[i] && abb_quadrants(hi)[i] != t.quadrants[i]) return false;
  }
  return true;
}

bool turn_matches(int written, const JointAngles& q) {
  const int bits = kuka_turn_bits(q);
  for (int i = 0; i < 6; ++i)
    if (((bits ^ written) >> i & 1) && std::abs(q[i]) > kSlack) return false;
  return true;
}

}  // namespace

std::vector<RobotTarget> read_robot_program(const std::map<std::string, std::string>& programs,
                                            const std::string& entry, RobotDialect dialect) {
  ReadState st;
  st.programs = &programs;
  st.dialect = dialect;
  const auto it = programs.find(entry);
  if (it == programs.end()) throw Error("robot program '" + entry + "' is not among the programs read");
  if (dialect == RobotDialect::AbbRapid) {
    index_procs(st);
    // PERS data of every module is declared when the task loads, before any runs.
    for (const auto& [name, text] : programs) {
      std::istringstream in(text);
      std::string raw;
      int line = 0;
      while (std::getline(in, raw)) {
        ++line;
        const std::string s = trimmed(raw.substr(0, raw.find('!')));
        if (s.rfind("PERS ", 0) == 0 || s.rfind("CONST ", 0) == 0) {
          ReadState decl;
          decl.pers_values = st.pers_values;
          read_rapid_line(decl, s, {name, line});
          st.pers_values = decl.pers_values;
        }
      }
    }
    st.pers_values.clear();
  }
  read_program(st, entry, it->second);
  return st.out;
}

std::vector<RobotTarget> read_robot_program(const std::string& text, RobotDialect dialect) {
  ReadState st;
  st.dialect = dialect;
  read_program(st, "", text);
  return st.out;
}

Frame robot_target_frame(const RobotCell& cell, const BeltStation& station, const RobotMove& move) {
  const Frame blade_in_base = robot_forward(cell.arm, move.joints) * cell.grip;
  return blade_in_base.inverse() * station.contact;
}

std::array<int, 3> abb_quadrants(const JointAngles& q) {
  auto quadrant = [](double rad) { return static_cast<int>(std::floor(rad_to_deg(rad) / 90.0 + 1e-9)); };
  return {quadrant(q[0]), quadrant(q[3]), quadrant(q[5])};
}

namespace {

// The wrist centre's x in the frame that turns with axis 1 (KUKA's "A1
// coordinate system"; ABB's "in front of / behind axis 1").
double wrist_x_in_axis1(const RobotArm& arm, const JointAngles& q) {
  const Vec3 c = robot_wrist_centre(arm, q);
  const double t1 = robot_opw_angles(arm, q)[0];
  return std::cos(t1) * c.x() + std::sin(t1) * c.y();
}

// The forearm's turn off the upper arm's line, θ3 + ψ3 (core/machine/robot.h):
// > 0 puts the wrist centre in front of the line through axes 2 and 3.
double elbow_angle(const RobotArm& arm, const JointAngles& q) {
  return robot_opw_angles(arm, q)[2] + std::atan2(arm.geometry.a2_mm, arm.geometry.c3_mm);
}

}  // namespace

int abb_cfx(const RobotArm& arm, const JointAngles& q) {
  int cfx = 0;
  if (wrist_x_in_axis1(arm, q) < 0) cfx |= 4;          // wrist centre behind axis 1
  if (std::sin(elbow_angle(arm, q)) < 0) cfx |= 2;     // behind the lower arm
  if (q[4] < 0) cfx |= 1;                              // axis 5 negative
  return cfx;
}

int kuka_status(const RobotArm& arm, const JointAngles& q) {
  int s = 0;
  if (wrist_x_in_axis1(arm, q) < 0) s |= 1;  // overhead area
  // φ: the A3 at which the wrist root point is on the line through A2 and A3
  // (θ3 + ψ3 = 0), in the controller's A3 values.
  const RobotJoint& j3 = arm.joints[2];
  const double phi = j3.sign * (-std::atan2(arm.geometry.a2_mm, arm.geometry.c3_mm) - j3.zero_rad);
  if (q[2] >= phi) s |= 2;
  const double a5 = rad_to_deg(q[4]);
  if ((a5 >= -180 && a5 < 0) || a5 >= 180) s |= 4;
  return s;
}

int kuka_turn_bits(const JointAngles& q) {
  int bits = 0;
  for (int i = 0; i < 6; ++i)
    if (q[i] < 0) bits |= 1 << i;
  return bits;
}

RobotVerifyReport verify_robot_program(const RobotCell& cell, const BeltStation& station,
                                       const RobotGrindingPlan& plan, const std::vector<RobotTarget>& targets,
                                       RobotDialect dialect, double position_tol_mm, double angle_tol_deg,
                                       const MassProperties* payload) {
  RobotVerifyReport r;
  std::vector<const RobotTarget*> cartesian;
  for (const RobotTarget& t : targets)
    if (!t.axis_move) cartesian.push_back(&t);
  r.moves = static_cast<int>(cartesian.size());
  if (cartesian.size() != plan.moves.size()) {
    r.problems.push_back("the program has " + std::to_string(cartesian.size()) + " Cartesian targets, the plan " +
                         std::to_string(plan.moves.size()) + " moves");
    return r;
  }
  if (targets.empty() || !targets.front().axis_move) {
    r.problems.push_back("the program does not start with a move to an axis position (PTP {A1 ..} / MoveAbsJ): "
                         "its first Cartesian target is reached from wherever the arm stands");
    return r;
  }
  const Vec3 wheel = station.contact.translation(), out = station.contact.linear().col(2);
  const RobotArm& arm = cell.arm;
  JointAngles previous = targets.front().joints;
  const RobotTarget* last_cartesian = nullptr;
  size_t k = 0;
  for (const RobotTarget& t : targets) {
    const std::string where = (t.file.empty() ? std::string() : t.file + " ") + "line " + std::to_string(t.line);
    if (t.axis_move) {
      previous = t.joints;
      last_cartesian = nullptr;
      continue;
    }
    const RobotMove& m = plan.moves[k++];
    const std::string at = where + " (move " + std::to_string(k) + ")";
    const Frame flange = t.external_tcp ? Frame(t.fixed * t.target.inverse() * t.held.inverse())
                                        : Frame(t.fixed * t.target * t.held.inverse());
    RobotIkOptions ik;
    ik.previous = previous;
    const auto solutions = robot_inverse(arm, flange, ik);
    const RobotSolution* chosen = nullptr;
    double best = 1e300;
    for (const RobotSolution& s : solutions) {
      if (!s.within_limits) continue;
      bool take;
      if (dialect == RobotDialect::AbbRapid) {
        take = abb_cfx(arm, s.joints) == t.cfx && quadrants_match(t, s.joints);  // ConfL / ConfJ on
      } else if (!t.linear) {
        take = kuka_status(arm, s.joints) == t.cfx && turn_matches(t.turn_bits, s.joints);  // PTP: S and T
      } else {
        take = kuka_status(arm, s.joints) == kuka_status(arm, previous);  // LIN keeps the configuration
      }
      const double time = robot_joint_move_time(arm, previous, s.joints);
      if (take && time < best) {
        best = time;
        chosen = &s;
      }
    }
    if (!chosen) {
      ++r.unreachable;
      r.problems.push_back(at + ": no solution in the configuration the controller takes is within the joint limits");
      continue;
    }
    const JointAngles& q = chosen->joints;
    if (dialect == RobotDialect::KukaKrl &&
        (kuka_status(arm, q) != t.cfx || !turn_matches(t.turn_bits, q))) {
      ++r.configuration_disagreements;
      r.problems.push_back(at + ": written S " + std::to_string(t.cfx) + " T " + std::to_string(t.turn_bits) +
                           ", the arm stands at S " + std::to_string(kuka_status(arm, q)) + " T " +
                           std::to_string(kuka_turn_bits(q)));
    }
    const bool same_config = dialect == RobotDialect::AbbRapid
                                 ? abb_cfx(arm, q) == abb_cfx(arm, m.joints)
                                 : kuka_status(arm, q) == kuka_status(arm, m.joints);
    if (!same_config) {
      ++r.configuration_flips;
      r.problems.push_back(at + ": the controller reaches it in another configuration than the plan's");
    }
    if (payload) {
      const double scale = payload->inertia_kg_mm2.norm();
      const bool same = t.load_known && std::abs(t.load.mass_kg - payload->mass_kg) <= 2.5e-3 &&
                        // RAPID's loads weigh at least 1 g each: a centre of gravity of grams means nothing
                        (payload->mass_kg < 0.1 || (t.load.cog_mm - payload->cog_mm).norm() <= 0.05) &&
                        (t.load.inertia_kg_mm2 - payload->inertia_kg_mm2).norm() <= std::max(5.0, 1e-3 * scale);
      if (!same) {
        ++r.load_disagreements;
        if (r.load_disagreements <= 3) {
          std::ostringstream msg;
          msg << at << ": ";
          if (!t.load_known) {
            msg << "no load is set";
          } else {
            msg << "the load in force on the flange is " << t.load.mass_kg << " kg at (" << t.load.cog_mm.transpose()
                << ") mm, inertia " << 1e-6 * t.load.inertia_kg_mm2.norm() << " kg m2 (the payload: "
                << payload->mass_kg << " kg at (" << payload->cog_mm.transpose() << ") mm, " << 1e-6 * scale
                << " kg m2; differing by " << (t.load.cog_mm - payload->cog_mm).norm() << " mm, "
                << 1e-6 * (t.load.inertia_kg_mm2 - payload->inertia_kg_mm2).norm() << " kg m2)";
          }
          r.problems.push_back(msg.str());
        }
      }
    }
    previous = q;
    for (int j = 0; j < 6; ++j) r.max_joint_deg = std::max(r.max_joint_deg, rad_to_deg(std::abs(q[j] - m.joints[j])));
    const Frame replayed = robot_forward(arm, q);
    const Vec3 contact = (replayed * cell.grip) * m.contact.point;
    const double dev = (contact - (wheel + m.offset_mm * out)).norm();
    const double ang = rotation_angle_deg(replayed.linear(), robot_forward(arm, m.joints).linear());
    r.max_position_mm = std::max(r.max_position_mm, dev);
    r.max_angle_deg = std::max(r.max_angle_deg, ang);
    if (dev > position_tol_mm)
      r.problems.push_back(at + ": the contact lands " + std::to_string(1e3 * dev) + " um from the plan's");
    else if (ang > angle_tol_deg)
      r.problems.push_back(at + ": the part is turned " + std::to_string(ang) + " deg from the plan");
    // The controller takes the longer of the path's and the reorientation's
    // time at their speeds: a grinding move whose reorientation needs more
    // time than its length at the feed is slowed below the feed.
    if (last_cartesian && !m.link && t.tcp_speed_mm_s > 0 && t.ori_speed_deg_s > 0) {
      const double length = (t.target.translation() - last_cartesian->target.translation()).norm();
      const double turn = rotation_angle_deg(t.target.linear(), last_cartesian->target.linear());
      if (turn / t.ori_speed_deg_s > 1.0005 * length / t.tcp_speed_mm_s + 1e-9) {
        ++r.feed_capped;
        if (r.feed_capped <= 3)
          r.problems.push_back(at + ": the reorientation " + std::to_string(turn) + " deg at " +
                               std::to_string(t.ori_speed_deg_s) + " deg/s takes longer than the " +
                               std::to_string(length) + " mm at " + std::to_string(t.tcp_speed_mm_s) + " mm/s");
      }
    }
    last_cartesian = &t;
  }
  return r;
}

}  // namespace bliskrun
