#pragma once
// The result of a Core operation: Core never prints and never exits; it returns a Status
// whose message names the input, what is wrong with it, and what to do.
#include <string>
#include <utility>

namespace hair
{

class Status
{
public:
  Status() = default;
  static Status Ok() { return Status(); }
  static Status Error(std::string message) { return Status(std::move(message)); }

  bool ok() const { return !Failed; }
  explicit operator bool() const { return !Failed; }
  const std::string& message() const { return Message; }

private:
  explicit Status(std::string message) : Failed(true), Message(std::move(message)) {}
  bool Failed = false;
  std::string Message;
};

} // namespace hair
