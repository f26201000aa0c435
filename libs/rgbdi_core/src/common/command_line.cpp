#include "rgbdi/common/command_line.h"

#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <memory>
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

std::string usageErrorLine(const std::string& tool, const std::string& message) {
  return tool + ": " + message + " (see " + tool + " --help)\n";
}

namespace {

std::vector<std::string> splitNames(const std::string& names) {
  std::vector<std::string> out;
  std::istringstream is(names);
  std::string n;
  while (std::getline(is, n, ',')) out.push_back(n);
  return out;
}

bool isLongName(const std::string& n) { return n.size() > 2 && n.rfind("--", 0) == 0; }
bool isShortName(const std::string& n) { return n.size() == 2 && n[0] == '-' && n[1] != '-'; }

constexpr const char* kEmptyValue = "empty value";

// "--name=value" is read by splitting at the first '=' where TCLAP 1.2 takes one delimiter for
// the whole process (a static); our tools accept both spellings. TCLAP calls trimFlag on every
// argument it tries, so the split applies to this option's own long name only.
void splitInline(const std::string& long_name, const std::string& arg_id, std::string& flag,
                 std::string& value) {
  const auto eq = flag.find('=');
  if (eq == std::string::npos || flag.compare(0, eq, "--" + long_name) != 0) return;
  value = flag.substr(eq + 1);
  flag.resize(eq);
  // An empty inline value would make TCLAP take the next argument instead.
  if (value.empty()) throw TCLAP::ArgParseException(kEmptyValue, arg_id);
}

class InlineValueArg : public TCLAP::ValueArg<std::string> {
 public:
  InlineValueArg(const std::string& flag, const std::string& name)
      : TCLAP::ValueArg<std::string>(flag, name, name, false, "", "value") {}
  void trimFlag(std::string& flag, std::string& value) const override {
    splitInline(getName(), toString(), flag, value);
  }
};

// MRPT's TCLAP hands a parse failure to the output object and returns false from parse(); this
// output keeps it for a UsageError instead of printing TCLAP's own usage text (ours is the
// tool's --help).
class KeepFailure : public TCLAP::CmdLineOutput {
 public:
  void usage(TCLAP::CmdLineInterface&) override {}
  void version(TCLAP::CmdLineInterface&) override {}
  void failure(TCLAP::CmdLineInterface&, TCLAP::ArgException& e) override {
    failed = true;
    error = e.error();
    id = e.argId();
    const std::string prefix = "Argument: ";
    if (id.rfind(prefix, 0) == 0) id.erase(0, prefix.size());
  }
  bool failed = false;
  std::string error, id;
};

// The user's message for a failure TCLAP reported; TCLAP names the argument by Arg::toString(),
// e.g. "-o (--out)", and words its errors for a developer.
std::string describeFailure(const KeepFailure& f, const std::vector<const TCLAP::Arg*>& declared) {
  std::string name = f.id;
  for (const TCLAP::Arg* a : declared)
    if (a->toString() == f.id) name = "--" + a->getName();
  if (f.error == "Missing a value for this argument!" || f.error == kEmptyValue)
    return name + " needs a value";
  if (f.error == "Argument already set!") return name + " is given more than once";
  // Only an argument with a '*' after its first character is matched by nothing: TCLAP
  // reserves '*' (it marks the letters of combined short flags it has taken).
  if (f.error == "Couldn't find match for argument")
    return "cannot read argument '" + f.id + "' (the option parser reserves '*')";
  return name + ": " + f.error;
}

}  // namespace

void CommandLine::declare(const std::string& names, Kind kind, bool* flag,
                          std::function<void(const std::string&)> set) {
  Option o;
  o.names = splitNames(names);
  int long_names = 0, short_names = 0;
  for (const std::string& n : o.names) {
    if (isLongName(n))
      ++long_names;
    else if (isShortName(n))
      ++short_names;
    else
      throw std::logic_error("CommandLine: '" + n + "' is no option name");
    if (find(n)) throw std::logic_error("CommandLine: " + n + " declared twice");
  }
  // TCLAP gives an argument at most one one-letter flag and exactly one long name.
  if (long_names == 0 || short_names > 1)
    throw std::logic_error("CommandLine: '" + names + "' needs one long name, one short at most");
  o.kind = kind;
  o.flag = flag;
  o.set = std::move(set);
  options_.push_back(std::move(o));
}

void CommandLine::flag(const std::string& names, bool* out) {
  declare(names, Kind::Flag, out, nullptr);
}

void CommandLine::value(const std::string& names, std::function<void(const std::string&)> set) {
  declare(names, Kind::Value, nullptr, std::move(set));
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
  std::vector<std::string> args(argv + 1, argv + argc);
  // Everything after "--" is positional. TCLAP would note "--" in a process-wide static that
  // nothing resets, so it never sees it.
  const auto rest = std::find(args.begin(), args.end(), std::string("--"));
  const std::vector<std::string> after_rest(rest == args.end() ? rest : rest + 1, args.end());
  args.erase(rest, args.end());
  // --help / --version first: they must work whatever else is wrong on the line.
  for (const std::string& a : args) {
    if (a == "-h" || a == "--help") return Outcome::Help;
    if (a == "--version") return Outcome::Version;
  }
  // TCLAP's own "--ignore_rest" switch would set that static too.
  for (const std::string& a : args)
    if (a.rfind("--ignore_rest", 0) == 0) throw UsageError("unknown option '" + a + "'");

  // One TCLAP argument per spelling; aliases ("--colour-topic,--color-topic") share a setter.
  struct Spelling {
    const Option* option;
    std::unique_ptr<TCLAP::Arg> arg;
  };
  std::vector<Spelling> spellings;
  for (const Option& o : options_) {
    std::string short_flag;
    for (const std::string& n : o.names)
      if (isShortName(n)) short_flag = n.substr(1);
    for (const std::string& n : o.names) {
      if (!isLongName(n)) continue;
      const std::string name = n.substr(2);
      std::unique_ptr<TCLAP::Arg> arg;
      if (o.kind == Kind::Flag)
        arg = std::make_unique<TCLAP::SwitchArg>(short_flag, name, name, false);
      else
        arg = std::make_unique<InlineValueArg>(short_flag, name);
      short_flag.clear();  // the short name belongs to the first long one
      spellings.push_back({&o, std::move(arg)});
    }
  }
  // (TCLAP tells an unlabeled argument from the others by its description.)
  TCLAP::UnlabeledMultiArg<std::string> unlabeled("positional", "positional arguments", false,
                                                  "argument");
  KeepFailure failure;
  {
    TCLAP::CmdLine cmd("", ' ', rgbdiVersion(), /*helpAndVersion=*/false);
    // TCLAP 1.2's setOutput forgets the StdOutput its constructor made (a leak LSan reports).
    delete cmd.getOutput();
    cmd.setOutput(&failure);
    for (Spelling& s : spellings) cmd.add(s.arg.get());
    cmd.add(unlabeled);
    std::vector<const char*> line{argc > 0 ? argv[0] : "tool"};
    for (const std::string& a : args) line.push_back(a.c_str());
    cmd.parse(static_cast<int>(line.size()), line.data());
  }
  if (failure.failed) {
    std::vector<const TCLAP::Arg*> declared;
    for (const Spelling& s : spellings) declared.push_back(s.arg.get());
    throw UsageError(describeFailure(failure, declared));
  }

  // TCLAP leaves what it matches to no option among the positionals, "--bogus" too.
  for (const std::string& a : unlabeled.getValue()) {
    if (a.size() < 2 || a[0] != '-') {
      positional_.push_back(a);
      continue;
    }
    const std::string name = a.rfind("--", 0) == 0 ? a.substr(0, a.find('=')) : a;
    const Option* o = find(name);
    if (o && o->kind == Kind::Flag) throw UsageError(name + " takes no value (got '" + a + "')");
    throw UsageError("unknown option '" + name + "'");
  }
  positional_.insert(positional_.end(), after_rest.begin(), after_rest.end());

  for (const Option& o : options_) {
    const TCLAP::Arg* given = nullptr;
    for (const Spelling& s : spellings) {
      if (s.option != &o || !s.arg->isSet()) continue;
      if (given)
        throw UsageError("--" + given->getName() + " and --" + s.arg->getName() +
                         " are the same option; give it once");
      given = s.arg.get();
      if (o.kind == Kind::Flag) {
        *o.flag = true;
        continue;
      }
      try {
        o.set(static_cast<InlineValueArg&>(*s.arg).getValue());
      } catch (const std::invalid_argument& e) {
        throw UsageError(e.what());
      }
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
