// Errors in input that keep their parts: where the bad value is (file,
// line), which key, column or field holds it, and what it must be. Code
// that catches one decides by these parts (and relocates the message
// with them), never by reading its text. what() is the one-line message.
//
// Two kinds, as the rest of the program throws them:
//  - InputError (std::runtime_error): bad input from a file (scenario and
//    sweep files, CSV data), "FILE:LINE: message";
//  - FieldError (std::invalid_argument): a value of a Config struct or a
//    command-line option outside its allowed range, found by Validate()
//    or an option check; the message is the thrower's own.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace ipmc {

// `text` with its line breaks replaced by spaces, so that every message
// is one line.
std::string OneLine(std::string text);

// What is wrong with an input.
enum class InputProblem {
  kSyntax,      // not a TOML or CSV document, or a row of the wrong length
  kUnreadable,  // a file that cannot be opened or read
  kMissing,     // a required key or column is absent
  kUnknownKey,  // a key the reader does not know
  kWrongType,   // a value of the wrong type
  kOtherKind,   // a key that belongs to the other kind of its table
  kBadValue,    // a value out of its allowed range, or a combination refused
};

// Where an input error is: the file and, when known, line and column
// (1-based; 0: unknown).
struct InputLocation {
  std::string file;
  std::uint32_t line = 0;
  std::uint32_t column = 0;
};

class InputError : public std::runtime_error {
 public:
  // what(): "FILE:LINE:COLUMN: MESSAGE", without ":LINE" or ":COLUMN"
  // where they are 0, on one line. `key`: the dotted key (or CSV column)
  // the message is about, "" if none; `allowed`: the allowed range or
  // values, "" if the message is not about a value.
  InputError(InputProblem problem, InputLocation where, std::string key, std::string message,
             std::string allowed = "");

  InputProblem problem() const { return problem_; }
  const InputLocation& where() const { return where_; }
  const std::string& key() const { return key_; }
  // The message without its location.
  const std::string& message() const { return message_; }
  const std::string& allowed() const { return allowed_; }

 private:
  InputProblem problem_;
  InputLocation where_;
  std::string key_;
  std::string message_;
  std::string allowed_;
};

class FieldError : public std::invalid_argument {
 public:
  // `field`: the Config field or option ("frequency_Hz", "--links");
  // `allowed`: its allowed range or values.
  FieldError(const std::string& message, std::string field, std::string allowed);

  const std::string& field() const { return field_; }
  const std::string& allowed() const { return allowed_; }

 private:
  std::string field_;
  std::string allowed_;
};

// Throws FieldError "WHO: OPTION must be ALLOWED, got GOT", the form of
// every command's option checks.
[[noreturn]] void ThrowOption(const std::string& who, const std::string& option,
                              const std::string& allowed, const std::string& got);
// ThrowOption(who, option, "finite and > 0", value) unless it is.
void RequireFinitePositive(const std::string& who, const std::string& option, double value);

}  // namespace ipmc
