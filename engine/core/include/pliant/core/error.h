// Errors every job and tool shares. InputError is bad input (exit code 2): its
// message always names the file, the JSON pointer and what was expected, e.g.
//   scenes/a.json: /grid/resolution/0: expected a positive integer, got -3
#pragma once
#include <stdexcept>
#include <string>

namespace pliant {

class InputError : public std::runtime_error {
 public:
  // file: as the user named it; pointer: RFC 6901 JSON pointer ("" for whole file).
  InputError(std::string file, std::string pointer, std::string problem);
  const std::string& file() const { return file_; }
  const std::string& pointer() const { return pointer_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_, pointer_, problem_;
};

// Thrown at a safe point after Progress::cancel(); jobs end with status "cancelled".
class CancelledError : public std::runtime_error {
 public:
  CancelledError() : std::runtime_error("cancelled") {}
};

// Exit codes of `pliant run` (ARCHITECTURE.md, job protocol).
enum ExitCode : int { kExitDone = 0, kExitInternal = 1, kExitInvalid = 2, kExitCancelled = 3 };

}  // namespace pliant
