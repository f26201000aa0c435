// MRPT exception texts carry a call-stack dump around the message; a user needs the message.
#pragma once

#include <string>

namespace rgbdi::live {

/// The "Message:" part of an MRPT exception text (or the whole first line of any other text).
inline std::string mrptMessage(const std::string& what) {
  std::string s = what;
  const std::string tag = "Message:";
  const auto m = s.find(tag);
  if (m != std::string::npos) s = s.substr(m + tag.size());
  const auto b = s.find_first_not_of(" \t\n");
  s = b == std::string::npos ? std::string() : s.substr(b);
  const auto nl = s.find('\n');
  if (nl != std::string::npos) s.resize(nl);
  return s;
}

}  // namespace rgbdi::live
