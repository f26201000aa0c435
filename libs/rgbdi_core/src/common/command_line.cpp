#include "rgbdi/common/command_line.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#ifndef RGBDI_VERSION_STRING
#error "RGBDI_VERSION_STRING comes from the CMake project version"
#endif

namespace rgbdi {

std::string exitStatusHelp() {
  return "Exit status: 0 success (warnings included); 1 error (unreadable input, failed run, "
         "output "
         "not\nwritten); 2 usage or configuration error; 3 damaged input processed up to the "
         "damage (the\noutputs of that part are written); 130 interrupted (Ctrl-C; the outputs of "
         "the part processed\nare written).\n";
}

const char* rgbdiVersion() { return RGBDI_VERSION_STRING; }

std::string versionLine(const std::string& tool) { return tool + " (rgbdi) " + rgbdiVersion(); }

namespace {
std::vector<std::string> splitNames(const std::string& names) {
  std::vector<std::string> out;
  std::istringstream is(names);
  std::string n;
  while (std::getline(is, n, ',')) out.push_back(n);
  return out;
}
}  // namespace

void CommandLine::flag(const std::string& names, bool* out) {
  Option o;
  o.names = splitNames(names);
  o.flag = out;
  options_.push_back(std::move(o));
}

void CommandLine::value(const std::string& names, std::function<void(const std::string&)> set) {
  Option o;
  o.names = splitNames(names);
  o.takes_value = true;
  o.set = std::move(set);
  options_.push_back(std::move(o));
}

void CommandLine::value(const std::string& names, std::string* out) {
  value(names, [out](const std::string& v) { *out = v; });
}

const CommandLine::Option* CommandLine::find(const std::string& name) const {
  for (const Option& o : options_)
    for (const std::string& n : o.names)
      if (n == name) return &o;
  return nullptr;
}

CommandLine::Outcome CommandLine::parse(int argc, const char* const* argv) {
  positional_.clear();
  const std::vector<std::string> args(argv + 1, argv + argc);
  // --help / --version first: they must work whatever else is wrong on the line.
  for (const std::string& a : args) {
    if (a == "--") break;
    if (a == "-h" || a == "--help") return Outcome::Help;
    if (a == "--version") return Outcome::Version;
  }
  bool options_done = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (options_done || arg.size() < 2 || arg[0] != '-') {
      positional_.push_back(arg);
      continue;
    }
    if (arg == "--") {
      options_done = true;
      continue;
    }
    std::string name = arg, inline_value;
    bool has_inline = false;
    const auto eq = arg.find('=');
    if (arg.rfind("--", 0) == 0 && eq != std::string::npos) {
      name = arg.substr(0, eq);
      inline_value = arg.substr(eq + 1);
      has_inline = true;
    }
    const Option* o = find(name);
    if (!o) throw UsageError("unknown option '" + name + "'");
    if (!o->takes_value) {
      if (has_inline) throw UsageError(name + " takes no value (got '" + arg + "')");
      *o->flag = true;
      continue;
    }
    std::string v;
    if (has_inline) {
      v = inline_value;
    } else {
      if (i + 1 >= args.size()) throw UsageError(name + " needs a value");
      v = args[++i];
    }
    try {
      o->set(v);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
  }
  return Outcome::Run;
}

double parseNumber(const std::string& option, const std::string& text, bool positive) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v) || v < 0.0 ||
      (positive && v == 0.0))
    throw UsageError(option + " needs a " + (positive ? "positive" : "non-negative") +
                     " number, got '" + text + "'");
  return v;
}

}  // namespace rgbdi
