#include "core/io/data_lines.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/common/error.h"
#include "core/common/progress.h"

namespace bliskrun::io_detail {

DataLines::DataLines(const std::string& text, std::string file) : file_(std::move(file)) {
  std::istringstream ss(text);
  for (std::string l; std::getline(ss, l);) {
    if ((lines_.size() & 1023) == 0) cancellation_point();
    if (!l.empty() && l.back() == '\r') l.pop_back();
    lines_.push_back(std::move(l));
  }
  if (!lines_.empty() && lines_[0].compare(0, 3, "\xEF\xBB\xBF") == 0) lines_[0].erase(0, 3);
}

const std::string& DataLines::take(const std::string& expected) {
  if ((next_ & 1023) == 0) cancellation_point();
  if (at_end()) throw DataError(file_, static_cast<long>(next_ + 1), "unexpected end of file; expected " + expected);
  return lines_[next_++];
}

void DataLines::skip_blank() {
  while (!at_end() && fields(peek()).empty()) ++next_;
}

void DataLines::fail(const std::string& message) const { throw DataError(file_, line(), message); }

std::vector<std::string> DataLines::fields(const std::string& line, char separator) {
  std::vector<std::string> out;
  std::string current;
  auto flush = [&] {
    if (!current.empty()) out.push_back(current);
    current.clear();
  };
  for (char c : line) {
    if (std::isspace(static_cast<unsigned char>(c)) || (separator != ' ' && c == separator))
      flush();
    else
      current += c;
  }
  flush();
  return out;
}

std::vector<double> DataLines::numbers(const std::string& line, int count, const std::string& what,
                                       char separator) const {
  const std::vector<std::string> f = fields(line, separator);
  if (count >= 0 && static_cast<int>(f.size()) != count)
    fail("expected " + std::to_string(count) + " numbers (" + what + "), got " + std::to_string(f.size()) +
         " fields");
  std::vector<double> out;
  out.reserve(f.size());
  for (const std::string& s : f) {
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0' || !std::isfinite(v))
      fail("expected a finite number (" + what + "), got '" + s + "'");
    out.push_back(v);
  }
  return out;
}

std::string read_text_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw DataError(path, 0, "cannot open the file for reading");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace bliskrun::io_detail
