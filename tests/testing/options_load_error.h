// The error an options struct's load() gives for an INI text: what the option tests compare with.
#pragma once

#include <string>

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::test {

/// The ConfigError message of reading `text` as the file `file_name` into Options::load(ini)
/// (a syntax error of the text included); "" when it loads.
template <class Options>
std::string optionsLoadError(const std::string& text, const std::string& file_name = "test.ini") {
  try {
    IniReader ini = IniReader::fromText(text, file_name);
    Options::load(ini);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

}  // namespace rgbdi::test
