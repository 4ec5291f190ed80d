#include "core/machine/program_reader.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "core/common/error.h"

namespace bliskrun {

namespace {

struct Token {
  enum Kind { Word, Keyword, Number, Parameter } kind;
  char letter = 0;       // Word
  std::string text;      // Keyword (upper case) / the raw text
  double value = 0;      // Word, Number; Parameter: the value assigned
  int column = 0;        // 1-based
  int line = 0;          // 1-based physical line (a Heidenhain block may span several)
  int index = 0;         // Parameter: n of "Qn="
};

[[noreturn]] void fail_at(const std::string& file, const Token& tok, const std::string& message) {
  throw DataError(file, tok.line, "column " + std::to_string(tok.column) + ": " + message);
}

class LineReader {
 public:
  LineReader(const std::string& file, int line) : file_(file), line_(line) {}

  [[noreturn]] void fail(int column, const std::string& message) const {
    throw DataError(file_, line_, "column " + std::to_string(column) + ": " + message);
  }

  std::vector<Token> tokenize(const std::string& s) const {
    std::vector<Token> out;
    size_t i = 0;
    while (i < s.size()) {
      const char c = s[i];
      const int col = static_cast<int>(i) + 1;
      if (std::isspace(static_cast<unsigned char>(c))) { ++i; continue; }
      if (c == ';') break;
      if (c == '(') {
        const size_t end = s.find(')', i);
        if (end == std::string::npos) fail(col, "comment '(' is not closed");
        i = end + 1;
        continue;
      }
      // Heidenhain "BEGIN PGM name MM": the name may mix letters, digits and
      // '_' ("BLADE_1_SUCTION"); it is one token, whatever it holds.
      if (out.size() >= 2 && out.back().kind == Token::Keyword && out.back().text == "PGM" &&
          out[out.size() - 2].kind == Token::Keyword &&
          (out[out.size() - 2].text == "BEGIN" || out[out.size() - 2].text == "END")) {
        size_t j = i;
        while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j]))) ++j;
        out.push_back(Token{Token::Keyword, 0, s.substr(i, j - i), 0, col});
        i = j;
        continue;
      }
      if (std::isalpha(static_cast<unsigned char>(c))) {
        size_t j = i;
        while (j < s.size() && (std::isalpha(static_cast<unsigned char>(s[j])) || s[j] == '_')) ++j;
        std::string run = s.substr(i, j - i);
        for (char& ch : run) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
        const bool number_follows = j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) ||
                                                     s[j] == '+' || s[j] == '-' || s[j] == '.' ||
                                                     s[j] == '=');
        if (run.size() == 1 && number_follows) {
          size_t k = j + (s[j] == '=' ? 1 : 0);
          Token t{Token::Word, run[0], run, 0, col};
          t.value = number(s, k, col + static_cast<int>(k - i));
          // Heidenhain cycle parameters: "Q339=+1" assigns parameter 339.
          if (run[0] == 'Q' && s[j] != '=' && k < s.size() && s[k] == '=') {
            if (!is_index(t.value)) fail(col, "expected a parameter number after Q");
            t.kind = Token::Parameter;
            t.index = static_cast<int>(t.value);
            ++k;
            t.value = number(s, k, col + static_cast<int>(k - i));
          }
          out.push_back(t);
          i = k;
        } else {
          out.push_back(Token{Token::Keyword, 0, run, 0, col});
          i = j;
        }
        continue;
      }
      if (std::isdigit(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.') {
        Token t{Token::Number, 0, "", 0, col};
        t.value = number(s, i, col);
        out.push_back(t);
        continue;
      }
      fail(col, std::string("unexpected character '") + c + "'");
    }
    for (Token& t : out) t.line = line_;
    return out;
  }

 private:
  static bool is_index(double v) { return v >= 0 && v == static_cast<double>(static_cast<long>(v)); }

  // Reads a decimal number at s[i]; advances i.
  double number(const std::string& s, size_t& i, int col) const {
    const size_t start = i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    bool digits = false;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) { ++i; digits = true; }
    if (i < s.size() && s[i] == '.') {
      ++i;
      while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) { ++i; digits = true; }
    }
    if (!digits) fail(col, "expected a number");
    return std::strtod(s.substr(start, i - start).c_str(), nullptr);
  }

  const std::string& file_;
  int line_;
};

bool is_integer(double v) { return std::abs(v - std::round(v)) < 1e-9; }

}  // namespace

std::vector<ProgramMove> read_program(const std::string& text, const MachineDefinition& machine,
                                      const ProgramReadOptions& options) {
  std::vector<ProgramMove> moves;
  // Modal state.
  MachineAxes axes = options.start;
  bool tcp = options.tcp;
  bool vector = false;
  std::array<int, 2> pending_reset{0, 0};
  FeedMode feed_mode = FeedMode::PerMinute;
  double feed = 0;
  int tool = 0;
  int motion = -1;  // 0 rapid, 1 feed, -1 not yet set
  int work_offset = 0;  // none selected yet

  size_t pos = 0;
  int line_no = 0;
  // The next physical line, without its end of line; false at the end.
  auto next_line = [&](std::string& line) {
    if (pos > text.size()) return false;
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  };
  // A line ending in '~' (after its comment, if any) continues on the next
  // one: the TNC writes a cycle's parameters one per line that way.
  auto continues = [](std::string& line) {
    const size_t last = line.find_last_not_of(" \t");
    if (last == std::string::npos || line[last] != '~') return false;
    line.erase(last);
    return true;
  };
  std::string line;
  while (next_line(line)) {
    const size_t first = line.find_first_not_of(" \t");
    if (first != std::string::npos && line[first] == '%') continue;  // tape start/end
    const int block_line = line_no;
    const LineReader reader(options.file_name, line_no);
    bool more = continues(line);
    std::vector<Token> tokens = reader.tokenize(line);
    while (more) {
      if (!next_line(line)) reader.fail(1, "the block ends in '~' but no line follows");
      more = continues(line);
      const std::vector<Token> rest = LineReader(options.file_name, line_no).tokenize(line);
      tokens.insert(tokens.end(), rest.begin(), rest.end());
    }
    if (tokens.empty()) continue;
    const auto fail = [&](const Token& tok, const std::string& message) { fail_at(options.file_name, tok, message); };
    Token block_start = tokens.front();  // errors about the whole block name its first column
    block_start.line = block_line;
    block_start.column = 1;

    bool axis_word = false, heidenhain_linear = false, fmax = false;
    int block_motion = -1;
    bool end_of_program = false;
    bool g54_1 = false;  // Fanuc's additional work offsets: G54.1 P<n> is offset 6 + n
    long p_word = -1;
    for (size_t t = 0; t < tokens.size(); ++t) {
      const Token& tok = tokens[t];
      if (tok.kind == Token::Number) {
        if (t == 0 && is_integer(tok.value) && tok.value >= 0) continue;  // Heidenhain block number
        fail(tok, "a number without an address letter");
      }
      if (tok.kind == Token::Parameter)
        fail(tok, "parameter Q" + std::to_string(tok.index) + " outside a cycle definition");
      if (tok.kind == Token::Keyword) {
        const std::string& k = tok.text;
        if (k == "BEGIN" || k == "END") {
          if (t + 1 >= tokens.size() || tokens[t + 1].text != "PGM")
            fail(tok, "expected PGM after " + k);
          end_of_program = k == "END";
          break;  // the program name and unit follow
        }
        if (k == "TOOL") {
          if (t + 2 >= tokens.size() || tokens[t + 1].text != "CALL" ||
              tokens[t + 2].kind != Token::Number || !is_integer(tokens[t + 2].value))
            fail(tok, "expected TOOL CALL <number>");
          tool = static_cast<int>(tokens[t + 2].value);
          t += 2;
          // Spindle axis and speed follow: "Z S12000".
          if (t + 1 < tokens.size() && tokens[t + 1].kind == Token::Keyword &&
              (tokens[t + 1].text == "X" || tokens[t + 1].text == "Y" || tokens[t + 1].text == "Z"))
            ++t;
          continue;
        }
        if (k == "FUNCTION") {
          if (t + 1 < tokens.size() && tokens[t + 1].text == "TCPM") {
            tcp = true;
            vector = false;  // PATHCTRL AXIS unless the block says VECTOR
            for (size_t j = t + 2; j + 1 < tokens.size(); ++j) {
              if (tokens[j].kind != Token::Keyword || tokens[j].text != "PATHCTRL") continue;
              if (tokens[j + 1].text == "VECTOR") vector = true;
              else if (tokens[j + 1].text != "AXIS") fail(tokens[j + 1], "expected PATHCTRL AXIS or PATHCTRL VECTOR");
            }
          } else if (t + 2 < tokens.size() && tokens[t + 1].text == "RESET" && tokens[t + 2].text == "TCPM") {
            tcp = false;
            vector = false;
          } else {
            fail(tok, "expected FUNCTION TCPM or FUNCTION RESET TCPM");
          }
          break;  // TCPM options follow
        }
        if (k == "CYCL") {
          // "CYCL DEF 247 DATUM SETTING ~ Q339=+n ;DATUM NUMBER" activates
          // row n of the preset table; no other cycle is read.
          const bool datum_setting =
              t + 4 < tokens.size() && tokens[t + 1].text == "DEF" && tokens[t + 2].kind == Token::Number &&
              tokens[t + 2].value == 247 && tokens[t + 3].text == "DATUM" && tokens[t + 4].text == "SETTING";
          if (!datum_setting) fail(tok, "unsupported cycle: expected CYCL DEF 247 DATUM SETTING");
          t += 4;
          int preset = -1;
          for (++t; t < tokens.size(); ++t) {
            const Token& q = tokens[t];
            if (q.kind != Token::Parameter || q.index != 339)
              fail(q, "expected Q339=<preset number> in CYCL DEF 247 (its only parameter)");
            if (preset >= 0) fail(q, "Q339 is given twice");
            if (!is_integer(q.value) || q.value < 0) fail(q, "expected a preset number >= 0 in Q339");
            preset = static_cast<int>(std::lround(q.value));
          }
          if (preset < 0) fail(tok, "CYCL DEF 247 without Q339 (the preset number)");
          work_offset = preset;
          break;
        }
        if (k == "L") { heidenhain_linear = true; continue; }
        if (k == "FMAX") { fmax = true; continue; }
        if (k == "TRAORI") { tcp = true; continue; }
        if (k == "TRAFOOF") { tcp = false; continue; }
        fail(tok, "unknown word '" + k + "'");
      }
      // Address words.
      const double v = tok.value;
      switch (tok.letter) {
        case 'N': case 'O': case 'S': case 'D': case 'H': break;
        case 'P':
          if (!is_integer(v) || v < 1) fail(tok, "expected P<n>, n >= 1 (G54.1 P<n>)");
          p_word = std::lround(v);
          break;
        case 'T': tool = static_cast<int>(v); break;
        case 'F':
          if (!(v > 0)) fail(tok, "expected a feed > 0");
          feed = v;
          break;
        case 'R':
          if (!heidenhain_linear || v != 0) fail(tok, "radius compensation is not supported (expected R0 in an L block)");
          break;
        case 'M': {
          if (!is_integer(v)) fail(tok, "expected an integer M code");
          if (v == 128) tcp = true;
          if (v == 129) tcp = false;
          if (v == 94) {
            // M94 [axis]: the display of a rotary axis reduced to [0, 360).
            std::array<bool, 2> which{true, true};
            if (t + 1 < tokens.size() && tokens[t + 1].kind == Token::Keyword && tokens[t + 1].text.size() == 1) {
              const char name = tokens[t + 1].text[0];
              which = {machine.rotary[0].name.size() == 1 && machine.rotary[0].name[0] == name,
                       machine.rotary[1].name.size() == 1 && machine.rotary[1].name[0] == name};
              if (!which[0] && !which[1])
                fail(tokens[t + 1], std::string("M94: machine '") + machine.name + "' has no rotary axis " + name);
              ++t;
            }
            for (int r = 0; r < 2; ++r) {
              if (!which[r]) continue;
              const int turns = static_cast<int>(std::floor(axes.rotary_rad[r] / (2 * kPi)));
              axes.rotary_rad[r] -= 2 * kPi * turns;
              pending_reset[r] += turns;
            }
          }
          break;
        }
        case 'G': {
          const double g = v;
          auto is = [&](double x) { return std::abs(g - x) < 1e-9; };
          if (is(0) || is(1)) block_motion = static_cast<int>(g);
          else if (is(93)) feed_mode = FeedMode::InverseTime;
          else if (is(94)) feed_mode = FeedMode::PerMinute;
          else if (is(43.4) || is(43.5)) tcp = true;
          else if (is(49)) tcp = false;
          else if (is(91)) fail(tok, "incremental coordinates (G91) are not supported");
          else if (is(20) || is(70)) fail(tok, "inch units are not supported");
          else if (is(2) || is(3)) fail(tok, "arcs (G2/G3) are not supported");
          else if (g >= 54 && g <= 59 && is_integer(g)) work_offset = static_cast<int>(g) - 53;
          else if (is(54.1)) g54_1 = true;
          else if (is(59.1) || is(59.2) || is(59.3)) work_offset = 6 + static_cast<int>(std::lround((g - 59) * 10));
          else if (g >= 505 && g <= 599 && is_integer(g)) work_offset = static_cast<int>(g) - 500;
          else if (!(is(90) || is(17) || is(21) || is(71) || is(40) || is(43) || is(61) || is(64) || is(80))) {
            std::ostringstream code;
            code << "unsupported G code G" << g;
            fail(tok, code.str());
          }
          break;
        }
        case 'X': case 'Y': case 'Z':
          axes.linear_mm[tok.letter - 'X'] = v;
          axis_word = true;
          break;
        case 'A': case 'B': case 'C': {
          int index = -1;
          for (int i = 0; i < 2; ++i)
            if (machine.rotary[i].name.size() == 1 && machine.rotary[i].name[0] == tok.letter) index = i;
          if (index < 0)
            fail(tok, std::string("machine '") + machine.name + "' has no axis " + tok.letter);
          axes.rotary_rad[index] = deg_to_rad(v);
          axis_word = true;
          break;
        }
        default:
          fail(tok, std::string("unsupported word '") + tok.letter + "'");
      }
    }
    if (g54_1) {
      if (p_word < 1) fail(block_start, "G54.1 without P<n> (the additional work offset)");
      work_offset = 6 + static_cast<int>(p_word);
    } else if (p_word >= 0) {
      fail(block_start, "a P word outside G54.1 P<n>");
    }
    // Kinematics that are always TCP (LinuxCNC trt) have no switch: G49 there
    // only cancels length compensation.
    if (options.tcp) tcp = true;
    if (heidenhain_linear) block_motion = fmax ? 0 : 1;
    else if (fmax) fail(block_start, "FMAX outside an L block");
    if (block_motion >= 0) motion = block_motion;
    if (axis_word || heidenhain_linear) {
      if (motion < 0) fail(block_start, "axis words before any G0/G1");
      ProgramMove m;
      m.line = block_line;
      m.kind = motion == 0 ? MoveKind::Rapid : MoveKind::Feed;
      m.axes = axes;
      m.tcp = tcp;
      m.vector = tcp && vector;
      m.rotary_reset = pending_reset;
      pending_reset = {0, 0};
      m.feed_mode = feed_mode;
      m.feed = feed;
      m.tool = tool;
      m.work_offset = work_offset;
      if (m.kind == MoveKind::Feed && !(feed > 0)) fail(block_start, "feed move without a feed (F)");
      moves.push_back(m);
    }
    if (end_of_program) break;
  }
  return moves;
}

}  // namespace bliskrun
