// MRPT exception texts carry a call-stack dump around the message; a user needs the message.
#pragma once

#include <exception>
#include <string>

namespace rgbdi::live {

/// The original message inside an MRPT exception text. MRPT 2.5 wraps an exception thrown inside
/// MRPT_START/MRPT_END as "Message: <text after the first ']'>" and "Location: <text before
/// it>" plus a call stack; a message of ours ("FILE [section] key: what") is split that way, so
/// it is put back together. Texts without that frame are returned whole (a bag whose topics are
/// not found lists them on the following lines).
inline std::string mrptMessage(const std::string& what) {
  const auto lineAfter = [&](const std::string& tag, std::string& out) {
    const auto p = what.find(tag);
    if (p == std::string::npos) return false;
    out = what.substr(p + tag.size());
    const auto nl = out.find('\n');
    if (nl != std::string::npos) out.resize(nl);
    return true;
  };
  std::string message, location;
  if (lineAfter("Message: ", message)) {
    if (lineAfter("Location: ", location) && location.find(".cpp:") == std::string::npos &&
        location.find(".h:") == std::string::npos)
      return location + "]" + message;
    const auto b = message.find_first_not_of(" \t");
    return b == std::string::npos ? std::string() : message.substr(b);
  }
  return what;
}

/// The message of the innermost exception (MRPT_END wraps the original one with
/// std::throw_with_nested), without MRPT's location and call stack.
inline std::string exceptionMessage(const std::exception& e) {
  try {
    std::rethrow_if_nested(e);
  } catch (const std::exception& inner) {
    return exceptionMessage(inner);
  } catch (...) {
  }
  return mrptMessage(e.what());
}

}  // namespace rgbdi::live
