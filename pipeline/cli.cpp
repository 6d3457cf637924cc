#include "pipeline/cli.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <sstream>

#include "pipeline/atomic_write.h"
#include "pipeline/error.h"
#include "pipeline/lower_extension.h"

namespace pipeline {

namespace {

double parse_double(const std::string& flag, const std::string& s) {
  std::size_t pos = 0;
  double v = 0;
  try {
    v = std::stod(s, &pos);
  } catch (...) {
    pos = 0;
  }
  // std::stod also reads hexadecimal ("0x10" is 16) and "infinity": decimal numbers only
  const bool decimal = s.find_first_not_of("0123456789+-.eE") == std::string::npos;
  if (!decimal || pos == 0 || pos != s.size() || !std::isfinite(v))
    throw Error(ErrorKind::usage, flag + ": expected a finite number, got '" + s + "'");
  return v;
}

}  // namespace

Cli::Cli(std::string program, std::string description)
    : program_(std::move(program)), description_(std::move(description)) {}

Cli& Cli::option(const std::string& s, const std::string& l, std::string* value,
                 const std::string& help, bool is_required) {
  Opt o{s, l, help};
  o.is_required = is_required;
  // An empty value is never a file name or a choice: `--restart "$STATE"` with STATE unset ran
  // solve from t = 0 as if no --restart had been given, for ten minutes.
  o.set = [value, l](const std::string& v) {
    if (v.empty()) throw Error(ErrorKind::usage, l + ": '' is empty: give a value, or leave " + l + " out");
    *value = v;
  };
  o.get = [value] { return *value; };
  opts_.push_back(o);
  return *this;
}

Cli& Cli::option(const std::string& s, const std::string& l, double* value, const std::string& help,
                 double min, double max) {
  Opt o{s, l, help};
  o.set = [value, l, min, max](const std::string& v) {
    const double d = parse_double(l, v);
    if (d < min || d > max)
      throw Error(ErrorKind::usage, l + ": " + v + " is out of range [" + format_number(min) + ", " +
                                        format_number(max) + "]");
    *value = d;
  };
  o.get = [value] { return format_number(*value); };
  if (min > -std::numeric_limits<double>::max() || max < std::numeric_limits<double>::max())
    o.range = format_number(min) + " to " + format_number(max);
  opts_.push_back(o);
  return *this;
}

Cli& Cli::option(const std::string& s, const std::string& l, int* value, const std::string& help,
                 int min, int max) {
  Opt o{s, l, help};
  o.set = [value, l, min, max](const std::string& v) {
    const double d = parse_double(l, v);
    if (d != std::floor(d)) throw Error(ErrorKind::usage, l + ": expected an integer, got '" + v + "'");
    if (d < min || d > max)
      throw Error(ErrorKind::usage, l + ": " + v + " is out of range [" + std::to_string(min) +
                                        ", " + std::to_string(max) + "]");
    *value = int(d);
  };
  o.get = [value] { return std::to_string(*value); };
  if (min > std::numeric_limits<int>::min() || max < std::numeric_limits<int>::max())
    o.range = std::to_string(min) + " to " + std::to_string(max);
  opts_.push_back(o);
  return *this;
}

Cli& Cli::option(const std::string& s, const std::string& l, std::uint64_t* value, const std::string& help) {
  Opt o{s, l, help};
  o.set = [value, l](const std::string& v) {
    const bool digits = !v.empty() && v.size() <= 20 && v.find_first_not_of("0123456789") == std::string::npos;
    errno = 0;
    const unsigned long long n = digits ? std::strtoull(v.c_str(), nullptr, 10) : 0;
    if (!digits || errno == ERANGE)
      throw Error(ErrorKind::usage, l + ": expected a whole number from 0 to " +
                                        std::to_string(std::numeric_limits<std::uint64_t>::max()) + ", got '" + v + "'");
    *value = n;
  };
  o.get = [value] { return std::to_string(*value); };
  opts_.push_back(o);
  return *this;
}

Cli& Cli::flag(const std::string& s, const std::string& l, bool* value, const std::string& help) {
  Opt o{s, l, help};
  o.is_flag = true;
  o.set = [value](const std::string&) { *value = true; };
  o.get = [value] { return std::string(*value ? "true" : "false"); };
  opts_.push_back(o);
  return *this;
}

Cli::Opt* Cli::find(const std::string& flag) {
  for (auto& o : opts_)
    if (flag == o.short_flag || flag == o.long_flag) return &o;
  return nullptr;
}

bool Cli::given(const std::string& long_flag) const {
  for (const auto& o : opts_)
    if (o.long_flag == long_flag) return o.seen;
  throw Error(ErrorKind::usage, program_ + " has no option " + long_flag);
}

bool Cli::parse(int argc, char** argv) {
  for (auto& o : opts_) o.seen = false;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i], value;
    if (arg == "-h" || arg == "--help") {
      std::fputs(usage().c_str(), stdout);
      return false;
    }
    const auto eq = arg.find('=');
    bool inline_value = false;
    if (arg.rfind("--", 0) == 0 && eq != std::string::npos) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
      inline_value = true;
    }
    Opt* o = find(arg);
    if (!o) throw Error(ErrorKind::usage, "unknown option '" + arg + "'");
    // Twice was last-wins (`--edge 2 --edge 3` used 3), and `--flag=false` set the flag: both
    // read as something the user did not mean.
    if (o->seen) throw Error(ErrorKind::usage, o->long_flag + " given twice: give each option once");
    if (o->is_flag && inline_value)
      throw Error(ErrorKind::usage, o->long_flag + " is a flag and takes no value, got '" + value + "'");
    if (!o->is_flag && !inline_value) {
      if (i + 1 >= argc) throw Error(ErrorKind::usage, arg + ": missing value");
      value = argv[++i];
    }
    o->set(value);
    o->seen = true;
  }
  for (const auto& o : opts_)
    if (o.is_required && !o.seen)
      throw Error(ErrorKind::usage, "missing required option " + o.long_flag);
  return true;
}

std::string Cli::usage() const {
  std::ostringstream ss;
  ss << "Usage: " << program_ << " [options]\n\n" << description_ << "\n\nOptions:\n";
  for (const auto& o : opts_) {
    std::string flags = o.short_flag.empty() ? "    " : o.short_flag + ", ";
    flags += o.long_flag + (o.is_flag ? "" : " VALUE");
    ss << "  " << flags;
    ss << std::string(flags.size() < 26 ? 26 - flags.size() : 1, ' ') << o.help;
    if (o.is_required) ss << " (required)";
    else if (!o.is_flag && !o.get().empty())
      ss << " [default: " << o.get() << (o.range.empty() ? "" : "; " + o.range) << "]";
    ss << "\n";
  }
  ss << "  -h, --help                show this help\n";
  return ss.str();
}

std::string Cli::resolved() const {
  std::string s;
  for (const auto& o : opts_) s += (s.empty() ? "" : " ") + o.long_flag.substr(2) + "=" + o.get();
  return s;
}

void require_extension(const std::string& option, const std::string& path, const std::vector<std::string>& extensions) {
  const std::string ext = lower_extension(path);
  if (std::find(extensions.begin(), extensions.end(), ext) != extensions.end()) return;
  std::string list;
  for (std::size_t i = 0; i < extensions.size(); ++i)
    list += (i == 0 ? "" : i + 1 == extensions.size() ? " or " : ", ") + extensions[i];
  throw Error(ErrorKind::usage, option + ": '" + path + "' must end in " + list);
}

void require_distinct_files(const std::vector<std::pair<std::string, std::string>>& files) {
  namespace fs = std::filesystem;
  auto same = [](const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::equivalent(a, b, ec)) return true;  // both exist: hard and symbolic links too
    const fs::path ca = fs::weakly_canonical(fs::absolute(a, ec), ec), cb = fs::weakly_canonical(fs::absolute(b, ec), ec);
    return !ec && ca == cb;
  };
  for (std::size_t i = 0; i < files.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (!files[i].second.empty() && !files[j].second.empty() && same(files[i].second, files[j].second))
        throw Error(ErrorKind::usage, files[i].first + " '" + files[i].second + "' is the same file as " +
                                          files[j].first + ": each file option needs a file of its own (an output must not replace an input)");
}

namespace {
// CGAL's assertion messages span four lines; every failure is one line on stderr.
std::string one_line(std::string message) {
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  for (std::size_t p; (p = message.find('\n')) != std::string::npos;) message.replace(p, 1, " / ");
  return message;
}
}  // namespace

int run_main(Cli& cli, int argc, char** argv, const std::function<int()>& body) {
  const std::string& prog = cli.program();
  // Under a file size limit (ulimit -f) the kernel's SIGXFSZ killed a stage mid-write with no
  // message and left its temporary file; ignored, the write fails with EFBIG, which the atomic
  // writers report (exit 4) after removing the temporary file.
  std::signal(SIGXFSZ, SIG_IGN);
  remove_temporary_files_on_signals();
  try {
    if (!cli.parse(argc, argv)) return 0;
    std::fprintf(stderr, "%s: options: %s\n", prog.c_str(), cli.resolved().c_str());
    return body();
  } catch (const Error& e) {
    // One line, also for a usage error: its pointer to --help goes at the end of the error line
    // rather than on a line of its own, so every failure is exactly one line on stderr.
    if (e.kind == ErrorKind::usage)
      std::fprintf(stderr, "%s: %s (see '%s --help')\n", prog.c_str(), one_line(e.what()).c_str(), prog.c_str());
    else
      std::fprintf(stderr, "%s: %s\n", prog.c_str(), one_line(e.what()).c_str());
    return int(e.kind);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: internal error: %s\n", prog.c_str(), one_line(e.what()).c_str());
    return int(ErrorKind::algorithm);
  } catch (const std::string& e) {  // the gmsh API throws its last error message as a string
    std::fprintf(stderr, "%s: %s\n", prog.c_str(), one_line(e).c_str());
    return int(ErrorKind::algorithm);
  } catch (...) {
    std::fprintf(stderr, "%s: internal error: unknown exception\n", prog.c_str());
    return int(ErrorKind::algorithm);
  }
}

}  // namespace pipeline
