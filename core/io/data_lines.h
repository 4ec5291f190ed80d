#pragma once
// Line-oriented reading shared by the section readers: every failure is a
// DataError naming the file and the 1-based line, and what was expected.
#include <string>
#include <vector>

namespace bliskrun::io_detail {

class DataLines {
 public:
  // Splits on LF, dropping a trailing CR and a leading UTF-8 BOM.
  DataLines(const std::string& text, std::string file);
  bool at_end() const { return next_ >= lines_.size(); }
  const std::string& peek() const { return lines_[next_]; }
  // The next line; DataError "unexpected end of file; expected <expected>" at the end.
  const std::string& take(const std::string& expected);
  void skip_blank();
  long line() const { return static_cast<long>(next_); }  // 1-based number of the last taken line
  const std::string& file() const { return file_; }
  [[noreturn]] void fail(const std::string& message) const;

  // Fields split on whitespace, and also on `separator` when it is not ' '.
  static std::vector<std::string> fields(const std::string& line, char separator = ' ');
  // The line's fields as finite numbers; exactly `count` of them unless count < 0.
  std::vector<double> numbers(const std::string& line, int count, const std::string& what,
                              char separator = ' ') const;

 private:
  std::vector<std::string> lines_;
  std::string file_;
  size_t next_ = 0;
};

std::string read_text_file(const std::string& path);

}  // namespace bliskrun::io_detail
