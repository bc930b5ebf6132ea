// InputError message format: "FILE: POINTER: PROBLEM" (empty parts omitted).
#include "pliant/core/error.h"

namespace pliant {
namespace {
std::string compose(const std::string& file, const std::string& pointer, const std::string& problem) {
  std::string msg;
  if (!file.empty()) msg += file + ": ";
  if (!pointer.empty()) msg += pointer + ": ";
  msg += problem;
  return msg;
}
}  // namespace

InputError::InputError(std::string file, std::string pointer, std::string problem)
    : std::runtime_error(compose(file, pointer, problem)),
      file_(std::move(file)),
      pointer_(std::move(pointer)),
      problem_(std::move(problem)) {}

}  // namespace pliant
