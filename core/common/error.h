#pragma once
// Errors raised by core. Every error a user can cause says *where* (a file and
// line, or an option key) and *what was expected*; the Lua layer adds the
// recipe's file:line on top.
#include <stdexcept>
#include <string>

namespace bliskrun {

// Base of all errors core throws on bad input or failed computation.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

// Malformed data file: the message is "<file>:<line>: <what was expected>".
class DataError : public Error {
 public:
  DataError(const std::string& file, long line, const std::string& message)
      : Error(file + ":" + std::to_string(line) + ": " + message),
        file_(file), line_(line) {}
  const std::string& file() const { return file_; }
  long line() const { return line_; }

 private:
  std::string file_;
  long line_;
};

// A parameter outside its valid range: names the parameter and why.
class ParameterError : public Error {
 public:
  ParameterError(const std::string& name, const std::string& message)
      : Error(name + ": " + message), name_(name) {}
  const std::string& name() const { return name_; }

 private:
  std::string name_;
};

// A long computation stopped at a safe point because it was asked to.
class Cancelled : public Error {
 public:
  explicit Cancelled(const std::string& what) : Error(what) {}
};

}  // namespace bliskrun
