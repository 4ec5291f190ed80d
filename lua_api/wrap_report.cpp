// bliskrun.report{path=, title=, subtitle=, sections = {...}}: one
// self-contained HTML page per run — a table of contents, sections with text,
// tables from Lua tables, SVG charts inline and PNG pictures as data URIs.
// No script, no stylesheet or font from the network: it opens offline in any
// browser and can be mailed as one file. Written atomically.
#include <array>
#include <cmath>
#include <limits>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "core/analysis/part_picture.h"
#include "core/common/atomic_file.h"
#include "core/common/error.h"
#include "core/common/xml_escape.h"
#include "lua_api/luax.h"
#include "lua_api/modules.h"
#include "lua_api/runner.h"
#include "lua_api/undercut_map.h"
#include "lua_api/wrap_geometry.h"

namespace bliskrun::lua_api {

namespace {

using luax::Field;
using luax::Kind;

std::string base64(const std::string& bytes) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                       (static_cast<unsigned char>(bytes[i + 1]) << 8) | static_cast<unsigned char>(bytes[i + 2]);
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], k[v & 63]};
  }
  if (i + 1 == bytes.size()) {
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    out += {k[v >> 18], k[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) | (static_cast<unsigned char>(bytes[i + 1]) << 8);
    out += {k[v >> 18], k[(v >> 12) & 63], k[(v >> 6) & 63], '='};
  }
  return out;
}

// A number as an engineer reads it in a table: 3 significant digits, never
// an exponent for the magnitudes a run reports (1234.5 -> "1235", 0.0013089
// -> "0.00131", 14.25 -> "14.3"); below 1e-4 the exponent is the readable
// form. Integers are written as they are.
std::string number_text(double x) {
  if (!std::isfinite(x)) return std::isnan(x) ? "NaN" : (x > 0 ? "inf" : "-inf");
  if (x == 0) return "0";
  char buf[48];
  const double a = std::fabs(x);
  if (a < 1e-4) {
    std::snprintf(buf, sizeof buf, "%.2e", x);
  } else {
    const int digits = static_cast<int>(std::floor(std::log10(a)));
    const int decimals = digits >= 2 ? 0 : 2 - digits;
    std::snprintf(buf, sizeof buf, "%.*f", decimals, x);
  }
  std::string out = buf;
  if (out == "-0" || out.find_first_not_of("-0.") == std::string::npos) out = "0";
  return out;
}

// A table cell: numbers to 3 significant digits, strings as they are.
std::string cell(lua_State* L, int idx) {
  if (lua_type(L, idx) == LUA_TNUMBER) {
    if (lua_isinteger(L, idx)) return std::to_string(lua_tointeger(L, idx));
    return number_text(lua_tonumber(L, idx));
  }
  if (lua_type(L, idx) == LUA_TBOOLEAN) return lua_toboolean(L, idx) ? "yes" : "no";
  if (lua_type(L, idx) == LUA_TSTRING) return xml_escape(lua_tostring(L, idx));
  if (lua_isnil(L, idx)) return "";
  throw ParameterError("table", "expected numbers, strings or booleans in the cells");
}

// The verdict block {pass=, requirements = {{name=, unit=, measured=,
// at_most= | at_least=, pass=, note=}, ...}} at idx, drawn before the table of
// contents so it is the first thing read. The caller (run_report.verdict)
// decides each requirement's pass; this only lays it out.
std::string html_verdict(lua_State* L, int idx) {
  const luax::Options v(
      L, idx, "bliskrun.report verdict",
      {Field{"pass", Kind::Boolean, true, std::nullopt, std::nullopt, "overall: every requirement passed", {}},
       Field{"overall", Kind::String, false, std::nullopt, std::nullopt, "\"PASS\" or \"FAIL\" (pass, in words)", {}},
       Field{"summary", Kind::String, false, std::nullopt, std::nullopt, "one line under the verdict", {}},
       Field{"requirements", Kind::Table, true, std::nullopt, std::nullopt, "list of requirements", {}}});
  const bool pass = v.boolean("pass", false);
  std::string out = std::string("<section id=\"verdict\" class=\"verdict ") + (pass ? "pass" : "fail") +
                    "\">\n<p class=\"overall\">Verdict: <strong>" + (pass ? "PASS" : "FAIL") + "</strong></p>\n";
  if (v.has("summary")) out += "<p>" + xml_escape(v.string("summary", "")) + "</p>\n";
  out +=
      "<table>\n<thead><tr><th>requirement</th><th>unit</th><th>limit</th><th>measured</th><th>result</th></tr>"
      "</thead>\n<tbody>\n";
  v.push_raw("requirements");
  const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, -1));
  for (lua_Integer k = 1; k <= n; ++k) {
    const std::string where = "verdict.requirements[" + std::to_string(k) + "]";
    if (lua_geti(L, -1, k) != LUA_TTABLE) throw ParameterError(where, "expected a table");
    const luax::Options r(
        L, lua_gettop(L), "bliskrun.report " + where,
        {Field{"name", Kind::String, true, std::nullopt, std::nullopt, "what is required", {}},
         Field{"unit", Kind::String, true, std::nullopt, std::nullopt, "unit of the limit and the measure", {}},
         Field{"measured", Kind::Any, false, std::nullopt, std::nullopt, "the run's value (nil: not measured)", {}},
         Field{"at_most", Kind::Number, false, std::nullopt, std::nullopt, "upper limit", {}},
         Field{"at_least", Kind::Number, false, std::nullopt, std::nullopt, "lower limit", {}},
         Field{"pass", Kind::Boolean, true, std::nullopt, std::nullopt, "this requirement passed", {}},
         Field{"note", Kind::String, false, std::nullopt, std::nullopt, "where or why", {}}});
    std::string limit;
    if (r.has("at_least")) limit = "&ge; " + number_text(r.number("at_least", 0));
    if (r.has("at_most")) limit += (limit.empty() ? "" : ", ") + std::string("&le; ") + number_text(r.number("at_most", 0));
    std::string measured = "not measured";
    if (r.has("measured")) {
      r.push_raw("measured");
      measured = cell(L, -1);
      lua_pop(L, 1);
    }
    if (r.has("note")) measured += " <span class=\"meta\">(" + xml_escape(r.string("note", "")) + ")</span>";
    const bool ok = r.boolean("pass", false);
    out += std::string("<tr class=\"") + (ok ? "pass" : "fail") + "\"><td>" + xml_escape(r.string("name", "")) +
           "</td><td>" + xml_escape(r.string("unit", "")) + "</td><td class=\"n\">" + limit +
           "</td><td class=\"n\">" + measured + "</td><td>" + (ok ? "PASS" : "FAIL") + "</td></tr>\n";
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  return out + "</tbody>\n</table>\n</section>\n";
}

// {columns = {...}, rows = {{...}, ...}} at idx -> <table>.
std::string html_table(lua_State* L, int idx, const std::string& where) {
  const luax::Options t(L, idx, "bliskrun.report " + where,
                        {Field{"columns", Kind::Table, true, std::nullopt, std::nullopt, "column headings, with units", {}},
                         Field{"rows", Kind::Table, true, std::nullopt, std::nullopt, "list of rows, one value per column", {}}});
  std::string out = "<table>\n<thead><tr>";
  t.push_raw("columns");
  const int cols = static_cast<int>(lua_rawlen(L, -1));
  if (cols < 1) throw ParameterError(where + ".columns", "expected at least one column");
  for (int c = 1; c <= cols; ++c) {
    lua_geti(L, -1, c);
    out += "<th>" + cell(L, -1) + "</th>";
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  out += "</tr></thead>\n<tbody>\n";
  t.push_raw("rows");
  const lua_Integer rows = static_cast<lua_Integer>(lua_rawlen(L, -1));
  for (lua_Integer r = 1; r <= rows; ++r) {
    if (lua_geti(L, -1, r) != LUA_TTABLE)
      throw ParameterError(where + ".rows[" + std::to_string(r) + "]", "expected a list of cells");
    if (static_cast<int>(lua_rawlen(L, -1)) != cols)
      throw ParameterError(where + ".rows[" + std::to_string(r) + "]",
                           "expected " + std::to_string(cols) + " cells (one per column), got " +
                               std::to_string(lua_rawlen(L, -1)));
    out += "<tr>";
    for (int c = 1; c <= cols; ++c) {
      lua_geti(L, -1, c);
      out += (lua_type(L, -1) == LUA_TNUMBER ? "<td class=\"n\">" : "<td>") + cell(L, -1) + "</td>";
      lua_pop(L, 1);
    }
    out += "</tr>\n";
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  return out + "</tbody>\n</table>\n";
}

const char* kStyle =
    "body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222;line-height:1.4}"
    "h1{font-size:1.6em}h2{font-size:1.25em;border-bottom:1px solid #ccc;margin-top:2em}"
    "table{border-collapse:collapse;margin:1em 0}th,td{border:1px solid #bbb;padding:.25em .6em}"
    "th{background:#f0f0f0;text-align:left}td.n{text-align:right;font-variant-numeric:tabular-nums}"
    "figure{margin:1em 0}img,svg{max-width:100%;height:auto}figcaption{color:#555;font-size:.9em}"
    "nav ol{padding-left:1.5em}.meta{color:#555}"
    ".verdict{border:3px solid;padding:.2em 1em;margin:1em 0}.verdict.pass{border-color:#2a7a2a;background:#eef8ee}"
    ".verdict.fail{border-color:#b00020;background:#fdeef0}.overall{font-size:1.5em;margin:.3em 0}"
    "tr.fail td{color:#b00020;font-weight:bold}";

int w_report(lua_State* L) {
  const luax::Options o(
      L, 1, "bliskrun.report",
      {Field{"path", Kind::String, true, std::nullopt, std::nullopt, "the page, an .html file", {}},
       Field{"title", Kind::String, true, std::nullopt, std::nullopt, "page title", {}},
       Field{"subtitle", Kind::String, false, std::nullopt, std::nullopt, "one line under the title", {}},
       Field{"verdict", Kind::Table, false, std::nullopt, std::nullopt,
             "{pass=, summary=, requirements=}: drawn first, above the contents", {}},
       Field{"sections", Kind::Table, true, std::nullopt, std::nullopt,
             "list of {title=, text=, table=, svg=, image=, caption=}", {}}});
  const std::string path = context(L).resolve_write(L, o.string("path", ""));
  if (path.size() < 5 || path.compare(path.size() - 5, 5, ".html") != 0)
    luax::error(L, "bliskrun.report: path: expected an .html file name, got \"" + o.string("path", "") + "\"");
  o.push_raw("sections");
  const int sections = lua_gettop(L);
  return luax::guarded(L, [&] {
    const std::string title = o.string("title", "");
    std::string toc, body, verdict;
    if (o.has("verdict")) {
      o.push_raw("verdict");
      verdict = html_verdict(L, lua_gettop(L));
      lua_pop(L, 1);
    }
    const lua_Integer n = static_cast<lua_Integer>(lua_rawlen(L, sections));
    for (lua_Integer k = 1; k <= n; ++k) {
      const std::string where = "sections[" + std::to_string(k) + "]";
      if (lua_geti(L, sections, k) != LUA_TTABLE) throw ParameterError(where, "expected a table");
      const luax::Options s(
          L, lua_gettop(L), "bliskrun.report " + where,
          {Field{"title", Kind::String, true, std::nullopt, std::nullopt, "section heading", {}},
           Field{"text", Kind::Any, false, std::nullopt, std::nullopt, "a paragraph, or a list of them", {}},
           Field{"table", Kind::Table, false, std::nullopt, std::nullopt, "{columns=, rows=}", {}},
           Field{"svg", Kind::String, false, std::nullopt, std::nullopt, "an SVG document, drawn inline", {}},
           Field{"image", Kind::String, false, std::nullopt, std::nullopt, "a PNG file in the out folder, inlined", {}},
           Field{"caption", Kind::String, false, std::nullopt, std::nullopt, "under the chart or picture", {}}});
      const std::string id = "s" + std::to_string(k);
      const std::string heading = s.string("title", "");
      toc += "<li><a href=\"#" + id + "\">" + xml_escape(heading) + "</a></li>\n";
      body += "<section id=\"" + id + "\">\n<h2>" + xml_escape(heading) + "</h2>\n";
      if (s.has("text")) {
        s.push_raw("text");
        if (lua_type(L, -1) == LUA_TSTRING) {
          body += "<p>" + xml_escape(lua_tostring(L, -1)) + "</p>\n";
        } else if (lua_istable(L, -1)) {
          for (lua_Integer p = 1; p <= static_cast<lua_Integer>(lua_rawlen(L, -1)); ++p) {
            lua_geti(L, -1, p);
            if (lua_type(L, -1) != LUA_TSTRING)
              throw ParameterError(where + ".text[" + std::to_string(p) + "]", "expected a string");
            body += "<p>" + xml_escape(lua_tostring(L, -1)) + "</p>\n";
            lua_pop(L, 1);
          }
        } else {
          throw ParameterError(where + ".text", "expected a string or a list of strings");
        }
        lua_pop(L, 1);
      }
      if (s.has("table")) {
        s.push_raw("table");
        body += html_table(L, lua_gettop(L), where + ".table");
        lua_pop(L, 1);
      }
      const std::string caption =
          s.has("caption") ? "<figcaption>" + xml_escape(s.string("caption", "")) + "</figcaption>\n" : "";
      if (s.has("svg")) {
        std::string svg = s.string("svg", "");
        if (svg.rfind("<?xml", 0) == 0) svg.erase(0, svg.find("?>") + 2);  // a declaration may not sit inside HTML
        const auto start = svg.find("<svg");
        if (start == std::string::npos || svg.find_first_not_of(" \t\r\n") != start)
          throw ParameterError(where + ".svg", "expected an SVG document (starting with <svg)");
        body += "<figure>\n" + svg.substr(start) + caption + "</figure>\n";
      }
      if (s.has("image")) {
        const std::string name = s.string("image", "");
        std::ifstream in(context(L).resolve_write(L, name), std::ios::binary);
        if (!in) throw ParameterError(where + ".image", "cannot read '" + name + "' in the out folder");
        std::ostringstream bytes;
        bytes << in.rdbuf();
        if (bytes.str().compare(0, 8, "\x89PNG\r\n\x1a\n") != 0)
          throw ParameterError(where + ".image", "expected a PNG file, '" + name + "' is not one");
        body += "<figure>\n<img alt=\"" + xml_escape(name) + "\" src=\"data:image/png;base64," + base64(bytes.str()) +
                "\">\n" + caption + "</figure>\n";
      }
      body += "</section>\n";
      lua_pop(L, 1);
    }
    std::string page = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
                       xml_escape(title) + "</title>\n<style>" + kStyle + "</style>\n</head>\n<body>\n<h1>" +
                       xml_escape(title) + "</h1>\n";
    if (o.has("subtitle")) page += "<p class=\"meta\">" + xml_escape(o.string("subtitle", "")) + "</p>\n";
    page += verdict + "<nav>\n<h2>Contents</h2>\n<ol>\n" + toc + "</ol>\n</nav>\n" + body + "</body>\n</html>\n";
    write_file_atomic(path, page);
    lua_pushstring(L, path.c_str());
    return 1;
  });
}

// bliskrun.paint_part{path =, pieces = {{name =, surface =, map =, samples_u =,
// samples_v =}, ...}, title =, footer =, scale_um =, width =, height =,
// view =, up =} -> the picture's path: the surfaces drawn in 3D with their
// maps' values (mm, shown in µm) painted on (core/analysis/part_picture.h,
// rendered by POV-Ray). A surface without a map is drawn plain.
int w_paint_part(lua_State* L) {
  const luax::Options o(
      L, 1, "bliskrun.paint_part",
      {Field{"path", Kind::String, true, std::nullopt, std::nullopt, "the picture, a .png file", {}},
       Field{"pieces", Kind::Table, true, std::nullopt, std::nullopt,
             "{{name =, surface =, map = an UndercutMap (optional), samples_u =, samples_v =}, ...}", {}},
       Field{"title", Kind::String, false, std::nullopt, std::nullopt, "over the picture", {}},
       Field{"footer", Kind::String, false, std::nullopt, std::nullopt, "one line under the part", {}},
       Field{"scale_um", Kind::Number, false, 1e-3, 1e5, "colour scale +-, µm (the run's maps' scale)", {}},
       Field{"width", Kind::Integer, false, 50, 8000, "rendered part, px; default 900", {}},
       Field{"height", Kind::Integer, false, 50, 8000, "rendered part, px; default 600", {}},
       Field{"view", Kind::Table, false, std::nullopt, std::nullopt, "{x, y, z} looked along; default face-on", {}},
       Field{"up", Kind::Table, false, std::nullopt, std::nullopt, "{x, y, z} up in the picture", {}},
       Field{"behind", Kind::Boolean, false, std::nullopt, std::nullopt,
             "the default view turned round (the first piece's back)", {}}});
  const std::string path = context(L).resolve_write(L, o.string("path", ""));
  std::vector<PaintedPiece> pieces;
  o.push_raw("pieces");
  const int t = lua_gettop(L);
  for (lua_Integer k = 1; k <= luaL_len(L, t); ++k) {
    const std::string where = "bliskrun.paint_part: pieces[" + std::to_string(k) + "]";
    if (lua_geti(L, t, k) != LUA_TTABLE) luax::error(L, where + ": expected {name =, surface =, map =}");
    const luax::Options po(
        L, lua_gettop(L), where,
        {Field{"name", Kind::String, false, std::nullopt, std::nullopt, "the surface's name", {}},
         Field{"surface", Kind::Any, true, std::nullopt, std::nullopt, "a Surface", {}},
         Field{"map", Kind::Any, false, std::nullopt, std::nullopt, "an UndercutMap over the surface (mm)", {}},
         Field{"samples_u", Kind::Integer, false, 2, 2000, "grid rows; default 60", {}},
         Field{"samples_v", Kind::Integer, false, 2, 2000, "grid columns; default 150", {}},
         Field{"u", Kind::Table, false, std::nullopt, std::nullopt, "{u0, u1}: the map's window; default {0, 1}", {}},
         Field{"v", Kind::Table, false, std::nullopt, std::nullopt, "{v0, v1}: the map's window; default {0, 1}", {}}});
    PaintedPiece p;
    p.name = po.string("name", "surface " + std::to_string(k));
    p.rows = static_cast<int>(po.integer("samples_u", 60));
    p.cols = static_cast<int>(po.integer("samples_v", 150));
    po.push_raw("surface");
    const auto surface = luax::check<SurfaceHandle>(L, -1).surface;
    lua_pop(L, 1);
    const HeatMap* map = nullptr;
    if (po.has("map")) {
      po.push_raw("map");
      map = &luax::check<LuaUndercutMap>(L, -1).map;
      lua_pop(L, 1);  // the table still holds the map
    }
    // The window the map covers (bliskrun.simulate's u, v), in [0, 1].
    std::array<double, 2> wu{0, 1}, wv{0, 1};
    read_unit_window(L, po, where, "u", wu[0], wu[1]);
    read_unit_window(L, po, where, "v", wv[0], wv[1]);
    for (int i = 0; i < p.rows; ++i)
      for (int j = 0; j < p.cols; ++j) {
        p.points.push_back(surface->point(wu[0] + (wu[1] - wu[0]) * i / (p.rows - 1),
                                          wv[0] + (wv[1] - wv[0]) * j / (p.cols - 1)));
        p.values.push_back(map ? 1e3 * undercut_map_nearest(*map, i, p.rows, j, p.cols)
                               : std::numeric_limits<double>::quiet_NaN());
      }
    pieces.push_back(std::move(p));
    lua_pop(L, 1);
  }
  lua_pop(L, 1);
  PartPictureOptions po;
  po.title = o.string("title", "");
  po.footer = o.string("footer", "");
  po.scale_max = o.number("scale_um", 0);
  po.width_px = static_cast<int>(o.integer("width", po.width_px));
  po.height_px = static_cast<int>(o.integer("height", po.height_px));
  if (o.has("view")) po.view = o.vec3("view", Vec3::Zero());
  if (o.has("up")) po.up = o.vec3("up", Vec3::Zero());
  po.behind = o.boolean("behind", false);
  return luax::guarded(L, [&] {
    write_part_picture_png(pieces, path, po);
    lua_pushstring(L, path.c_str());
    return 1;
  });
}

// bliskrun.part_renderer_available() -> true when POV-Ray can be run.
int w_part_renderer_available(lua_State* L) {
  lua_pushboolean(L, part_renderer_available());
  return 1;
}

}  // namespace

void open_report(lua_State* L) {
  static const luaL_Reg functions[] = {{"report", w_report}, {"paint_part", w_paint_part},
                                       {"part_renderer_available", w_part_renderer_available}, {nullptr, nullptr}};
  luaL_setfuncs(L, functions, 0);
}

}  // namespace bliskrun::lua_api
