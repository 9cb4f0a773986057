// debris_fuzz: a coverage-guided mutation fuzzer for the readers of outside data (tests/fuzz/targets.cpp),
// written for g++ so that it runs the very libraries the executables link, built with AddressSanitizer and
// UndefinedBehaviorSanitizer (the CI's build-asan). The readers' sources are compiled with
// -fsanitize-coverage=trace-pc (cmake/DebrisFuzz.cmake), and an input that reaches an edge of their code not
// seen before, or an edge a new number of times (power-of-two classes), joins the corpus that later inputs
// are mutated from.
//
//   debris_fuzz list
//   debris_fuzz run TARGET [--runs N] [--seconds S] [--seed K] [--timeout T] [--max-len B]
//                          [--artifacts DIR] [--save-corpus DIR] SEEDS...
//   debris_fuzz replay TARGET INPUTS...
//
// SEEDS and INPUTS are files or directories (run: the files under a directory whose names end as the target
// expects; replay: every file under it). `replay` runs each input once (a committed corpus of past findings
// as a regression test); `run` runs the seeds, then mutants until N inputs or S seconds. Every input must
// end in a result or in the reader's named error: any other exception, a sanitizer report, an input that
// runs past T seconds, or (under ASan) one allocation past 512 MiB or a resident size past 3 GiB stops the
// fuzzer with status != 0 and writes the input to DIR (default fuzz-artifacts) as crash-* or timeout-*.
#include <cxxabi.h>
#include <dlfcn.h>
#include <cctype>
#include <fcntl.h>
#include <signal.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <typeinfo>
#include <vector>

#include "tests/fuzz/fuzz.hpp"

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/common_interface_defs.h>
// The fuzzer's own defaults (ASAN_OPTIONS may override them): one allocation past 512 MiB or a resident size
// past 3 GiB is a finding (an input must not make a reader allocate without bound); leaks are findings.
extern "C" const char* __asan_default_options() {
  return "max_allocation_size_mb=512:hard_rss_limit_mb=3072:detect_leaks=1:allocator_may_return_null=0";
}
extern "C" const char* __ubsan_default_options() { return "print_stacktrace=1:halt_on_error=1"; }
#endif

extern "C" std::uint8_t debris_fuzz_edges[1 << 16];  // tests/fuzz/coverage.cpp

namespace {

namespace fs = std::filesystem;
using debris::fuzz::Outcome;
using debris::fuzz::Target;
using Clock = std::chrono::steady_clock;

// ---- what a crash handler needs, set before each input --------------------------------------------------

const std::string* g_input = nullptr;
char g_crash_path[4096] = "";
char g_timeout_path[4096] = "";

// Async-signal-safe: writes the current input to `path`.
void dump_input(const char* path) {
  if (g_input == nullptr || path[0] == 0) return;
  const int fd = ::open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) return;
  const char* p = g_input->data();
  std::size_t left = g_input->size();
  while (left > 0) {
    const ssize_t w = ::write(fd, p, left);
    if (w <= 0) break;
    p += w;
    left -= static_cast<std::size_t>(w);
  }
  ::close(fd);
  const char note[] = "\ndebris_fuzz: the input is saved as ";
  [[maybe_unused]] ssize_t r = ::write(2, note, sizeof note - 1);
  r = ::write(2, path, std::strlen(path));
  r = ::write(2, "\n", 1);
}

void on_sanitizer_death() { dump_input(g_crash_path); }

void on_timeout(int) {
  const char note[] = "\ndebris_fuzz: finding: an input ran past the time limit\n";
  [[maybe_unused]] ssize_t r = ::write(2, note, sizeof note - 1);
#if defined(__SANITIZE_ADDRESS__)
  __sanitizer_print_stack_trace();
#endif
  dump_input(g_timeout_path);
  ::_exit(70);
}

void arm_timer(double seconds) {
  itimerval t{};
  t.it_value.tv_sec = static_cast<time_t>(seconds);
  t.it_value.tv_usec = static_cast<suseconds_t>((seconds - static_cast<double>(t.it_value.tv_sec)) * 1e6);
  setitimer(ITIMER_REAL, &t, nullptr);
}

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ULL;
  return h;
}

std::string hex(std::uint64_t v) {
  char b[17];
  std::snprintf(b, sizeof b, "%016llx", static_cast<unsigned long long>(v));
  return b;
}

std::string demangle(const char* name) {
  int status = 0;
  char* d = abi::__cxa_demangle(name, nullptr, nullptr, &status);
  std::string out = status == 0 && d ? d : name;
  std::free(d);
  return out;
}

std::string read_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

/// The files named by `paths`: files as given, directories walked in name order (filtered by `endings`
/// unless it is empty; hidden files and README.md skipped).
std::vector<fs::path> collect(const std::vector<std::string>& paths, const std::vector<std::string>& endings) {
  std::vector<fs::path> out;
  for (const std::string& p : paths) {
    if (fs::is_regular_file(p)) {
      out.emplace_back(p);
      continue;
    }
    if (!fs::is_directory(p)) {
      std::cerr << "debris_fuzz: no such file or directory: " << p << "\n";
      std::exit(2);
    }
    std::vector<fs::path> found;
    for (const auto& e : fs::recursive_directory_iterator(p)) {
      if (!e.is_regular_file()) continue;
      const std::string name = e.path().filename().string();
      if (name.empty() || name[0] == '.' || name == "README.md") continue;
      bool ok = endings.empty();
      for (const std::string& end : endings)
        ok = ok || (name.size() > end.size() && name.compare(name.size() - end.size(), end.size(), end) == 0 &&
                    name[name.size() - end.size() - 1] == '.');
      if (ok) found.push_back(e.path());
    }
    std::sort(found.begin(), found.end());
    out.insert(out.end(), found.begin(), found.end());
  }
  return out;
}

// ---- the executor: one input, its outcome and the coverage it reached ------------------------------------

struct Counts {
  long runs = 0, accepted = 0, rejected = 0, skipped = 0;
};

class Executor {
 public:
  Executor(const Target& t, double timeout, const std::string& artifacts) : t_(t), timeout_(timeout), artifacts_(artifacts) {
    fs::create_directories(artifacts_);
    struct sigaction sa{};
    sa.sa_handler = on_timeout;
    sigaction(SIGALRM, &sa, nullptr);
#if defined(__SANITIZE_ADDRESS__)
    __sanitizer_set_death_callback(on_sanitizer_death);
    // GCC links UBSan as a library of its own, with its own copy of the death callback: set that one too,
    // so that an undefined-behaviour report also saves the input.
    if (void* ubsan = dlopen("libubsan.so.1", RTLD_LAZY | RTLD_NOLOAD)) {
      using SetCallback = void (*)(void (*)());
      if (auto set = reinterpret_cast<SetCallback>(dlsym(ubsan, "__sanitizer_set_death_callback"))) set(on_sanitizer_death);
    }
#endif
  }

  /// Runs one input; returns whether it reached new coverage. A finding ends the process.
  bool execute(const std::string& input) {
    const std::string tag = t_.name + "-" + hex(fnv1a(input));
    std::snprintf(g_crash_path, sizeof g_crash_path, "%s/crash-%s", artifacts_.c_str(), tag.c_str());
    std::snprintf(g_timeout_path, sizeof g_timeout_path, "%s/timeout-%s", artifacts_.c_str(), tag.c_str());
    g_input = &input;
    std::memset(debris_fuzz_edges, 0, sizeof debris_fuzz_edges);
    arm_timer(timeout_);
    try {
      const Outcome o = t_.run(input);
      ++(o == Outcome::skipped ? counts.skipped : counts.accepted);
    } catch (const std::exception& e) {
      if (!t_.named_error(e)) finding("uncaught " + demangle(typeid(e).name()) + ": " + e.what());
      ++counts.rejected;
    } catch (...) {
      finding("an exception that is not a std::exception");
    }
    arm_timer(0);
    g_input = nullptr;
    ++counts.runs;
    return novel();
  }

  std::size_t edges() const { return edges_; }
  Counts counts;

 private:
  [[noreturn]] void finding(const std::string& what) {
    std::cerr << "debris_fuzz: finding in target " << t_.name << ": " << what << "\n";
    dump_input(g_crash_path);
    std::abort();
  }

  static std::uint8_t bucket(std::uint8_t n) {
    if (n == 0) return 0;
    if (n <= 3) return static_cast<std::uint8_t>(1u << (n - 1));  // 1, 2, 4
    if (n < 8) return 8;
    if (n < 16) return 16;
    if (n < 32) return 32;
    if (n < 128) return 64;
    return 128;
  }

  bool novel() {
    bool fresh = false;
    for (std::size_t i = 0; i < seen_.size(); ++i) {
      const std::uint8_t b = bucket(debris_fuzz_edges[i]);
      if ((b & ~seen_[i]) == 0) continue;
      if (seen_[i] == 0) ++edges_;
      seen_[i] |= b;
      fresh = true;
    }
    return fresh;
  }

  const Target& t_;
  double timeout_;
  std::string artifacts_;
  std::array<std::uint8_t, 1 << 16> seen_{};
  std::size_t edges_ = 0;
};

// ---- the mutator -----------------------------------------------------------------------------------------

const std::vector<std::string> kNumbers = {
    "0", "-0", "1", "-1", "2", "3", "4", "7", "8", "16", "0.5", "1.5", "-0.5", "255", "256", "65535", "65536",
    "2147483647", "2147483648", "-2147483648", "-2147483649", "4294967295", "4294967296", "9223372036854775807",
    "9223372036854775808", "-9223372036854775809", "18446744073709551616", "99999999999999999999999", "1e6", "1e7",
    "1e9", "1e12", "1e18", "1e308", "1e309", "-1e308", "1e-308", "4.9e-324", "1e-400", "nan", "NaN", ".nan",
    "inf", "-inf", ".inf", "-.inf", "0x7fffffff", "1e", "--1", "1..2", "+", "."};

const std::vector<std::string> kSyntax = {
    ": ", "- ", "[", "]", "{", "}", ", ", "\n", "  ", "&a ", "*a", "<<: *a\n", "!!str ", "!!binary ", "!!int ",
    "~", "null", "'", "\"", "#", "---\n", "...\n", "? ", "|\n", ">\n", "\t", ",", " ", "$", "\r\n", "\0"};

class Mutator {
 public:
  Mutator(std::uint64_t seed, std::size_t max_len) : rng_(seed), max_len_(max_len) {
    dict_.insert(dict_.end(), kSyntax.begin(), kSyntax.end());
  }

  /// Words of the seeds (keys, units, section names) join the dictionary.
  void learn(const std::string& text) {
    std::string word;
    for (char c : text + " ") {
      const bool part = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '$' || c == '.' || c == '^' || c == '/';
      if (part) {
        word += c;
      } else {
        if (word.size() >= 2 && word.size() <= 40 && words_.insert(word).second) dict_.push_back(word);
        word.clear();
      }
    }
  }

  std::string mutate(const std::string& parent, const std::vector<std::string>& corpus) {
    std::string s = parent;
    const int n = 1 + static_cast<int>(below(below(8) + 1));
    for (int k = 0; k < n; ++k) once(s, corpus);
    if (s.size() > max_len_) s.resize(max_len_);
    return s;
  }

  std::size_t below(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng_() % n); }

 private:
  const std::string& pick(const std::vector<std::string>& v) { return v[below(v.size())]; }

  void once(std::string& s, const std::vector<std::string>& corpus) {
    const std::size_t pos = below(s.size() + 1);
    switch (below(12)) {
      case 0:  // flip a bit
        if (!s.empty()) s[below(s.size())] ^= static_cast<char>(1u << below(8));
        break;
      case 1:  // a random byte
        if (!s.empty()) s[below(s.size())] = static_cast<char>(below(256));
        break;
      case 2:  // insert random bytes
        s.insert(pos, std::string(1 + below(4), static_cast<char>(below(256))));
        break;
      case 3:  // erase a range
        if (!s.empty()) s.erase(below(s.size()), 1 + below(std::min<std::size_t>(s.size(), below(2) ? 8 : 256)));
        break;
      case 4: {  // copy a range elsewhere
        if (s.empty()) break;
        const std::size_t from = below(s.size());
        const std::string piece = s.substr(from, 1 + below(std::min<std::size_t>(s.size() - from, 128)));
        s.insert(below(s.size() + 1), piece);
        break;
      }
      case 5:  // insert a dictionary word or syntax
        s.insert(pos, pick(dict_));
        break;
      case 6:  // overwrite with a dictionary word
        if (!s.empty()) {
          const std::string& w = pick(dict_);
          const std::size_t at = below(s.size());
          s.replace(at, std::min(w.size(), s.size() - at), w);
        }
        break;
      case 7:  // replace a number with an awkward one
      case 8: {
        std::vector<std::pair<std::size_t, std::size_t>> runs;
        for (std::size_t i = 0; i < s.size();) {
          if (std::isdigit(static_cast<unsigned char>(s[i]))) {
            std::size_t j = i;
            while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.' || s[j] == 'e' ||
                                    s[j] == 'E' || s[j] == '-' || s[j] == '+'))
              ++j;
            runs.emplace_back(i, j - i);
            i = j;
          } else {
            ++i;
          }
        }
        if (runs.empty()) {
          s.insert(pos, pick(kNumbers));
        } else {
          const auto [at, len] = runs[below(runs.size())];
          s.replace(at, len, below(4) == 0 ? std::to_string(static_cast<long long>(rng_() >> below(64))) : pick(kNumbers));
        }
        break;
      }
      case 9:  // line: delete, duplicate or swap
      case 10: {
        std::vector<std::string> lines;
        std::size_t start = 0;
        for (std::size_t i = 0; i <= s.size(); ++i)
          if (i == s.size() || s[i] == '\n') {
            lines.push_back(s.substr(start, i - start));
            start = i + 1;
          }
        if (lines.empty()) break;
        const std::size_t a = below(lines.size()), b = below(lines.size());
        switch (below(3)) {
          case 0: lines.erase(lines.begin() + static_cast<long>(a)); break;
          case 1: lines.insert(lines.begin() + static_cast<long>(a), lines[b]); break;
          default: std::swap(lines[a], lines[b]);
        }
        std::string joined;
        for (std::size_t i = 0; i < lines.size(); ++i) joined += (i ? "\n" : "") + lines[i];
        s = joined;
        break;
      }
      default: {  // splice in a piece of another corpus entry
        const std::string& other = pick(corpus);
        if (other.empty()) break;
        const std::size_t from = below(other.size());
        s.insert(pos, other.substr(from, 1 + below(std::min<std::size_t>(other.size() - from, 512))));
      }
    }
  }

  std::mt19937_64 rng_;
  std::size_t max_len_;
  std::vector<std::string> dict_;
  std::set<std::string> words_;
};

// ---- command line ------------------------------------------------------------------------------------------

struct Options {
  std::string mode, target;
  long runs = -1;
  double seconds = -1;
  std::uint64_t seed = 1;
  double timeout = 10;
  std::size_t max_len = 1 << 20;
  std::string artifacts = "fuzz-artifacts", save_corpus;
  std::vector<std::string> paths;
};

[[noreturn]] void usage(const std::string& why) {
  std::cerr << "debris_fuzz: " << why
            << "\nusage: debris_fuzz list\n"
               "       debris_fuzz run TARGET [--runs N] [--seconds S] [--seed K] [--timeout T] [--max-len B]\n"
               "                              [--artifacts DIR] [--save-corpus DIR] SEEDS...\n"
               "       debris_fuzz replay TARGET INPUTS...\n";
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  if (argc < 2) usage("no command");
  o.mode = argv[1];
  if (o.mode == "list") return o;
  if (o.mode != "run" && o.mode != "replay") usage("unknown command '" + o.mode + "'");
  if (argc < 3) usage("no target");
  o.target = argv[2];
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(a + " needs a value");
      return argv[++i];
    };
    try {
      if (a == "--runs") o.runs = std::stol(value());
      else if (a == "--seconds") o.seconds = std::stod(value());
      else if (a == "--seed") o.seed = std::stoull(value());
      else if (a == "--timeout") o.timeout = std::stod(value());
      else if (a == "--max-len") o.max_len = std::stoul(value());
      else if (a == "--artifacts") o.artifacts = value();
      else if (a == "--save-corpus") o.save_corpus = value();
      else if (a.rfind("--", 0) == 0) usage("unknown option " + a);
      else o.paths.push_back(a);
    } catch (const std::logic_error&) {
      usage("bad value for " + a);
    }
  }
  if (o.mode == "run" && o.runs < 0 && o.seconds < 0) usage("run needs --runs or --seconds");
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const Options opt = parse(argc, argv);
  const fs::path scratch = fs::temp_directory_path() / ("debris_fuzz_" + std::to_string(::getpid()));
  fs::remove_all(scratch);
  fs::create_directories(scratch);
  const std::vector<Target> targets = debris::fuzz::all_targets(scratch.string());
  if (opt.mode == "list") {
    for (const Target& t : targets) std::cout << t.name << "\t" << t.about << "\n";
    fs::remove_all(scratch);
    return 0;
  }
  const auto it = std::find_if(targets.begin(), targets.end(), [&](const Target& t) { return t.name == opt.target; });
  if (it == targets.end()) usage("unknown target '" + opt.target + "' (debris_fuzz list names them)");
  const Target& target = *it;

  if (target.prepare) target.prepare();
  Executor ex(target, opt.timeout, opt.artifacts);
  const auto t0 = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };

  std::vector<std::string> corpus;
  const std::vector<fs::path> files = collect(opt.paths, opt.mode == "replay" ? std::vector<std::string>{} : target.seed_endings);
  for (const fs::path& f : files) corpus.push_back(read_bytes(f));
  // The built-in seeds too (the checkpoint targets have no seed files: their seeds are mutation programs
  // over a checkpoint written at start-up), so a replay runs every target's seeds.
  if (target.builtin_seeds)
    for (std::string& s : target.builtin_seeds()) corpus.push_back(std::move(s));
  if (corpus.empty()) usage("no inputs or seeds for " + target.name);
  const std::size_t seeds = corpus.size();

  for (std::size_t k = 0; k < seeds; ++k) {
    if (opt.mode == "replay") std::cerr << "replay " << (k < files.size() ? files[k].string() : "builtin") << "\n";
    ex.execute(corpus[k]);
  }

  std::size_t found = 0;
  if (opt.mode == "run") {
    Mutator m(opt.seed, opt.max_len);
    for (const std::string& s : corpus) m.learn(s.substr(0, 1 << 16));
    if (!opt.save_corpus.empty()) fs::create_directories(opt.save_corpus);
    while ((opt.runs < 0 || ex.counts.runs < opt.runs) && (opt.seconds < 0 || elapsed() < opt.seconds)) {
      // Newer entries (those that found something) are picked as often as all the seeds together.
      const bool recent = corpus.size() > seeds && m.below(2) == 0;
      const std::size_t parent = recent ? seeds + m.below(corpus.size() - seeds) : m.below(corpus.size());
      std::string child = m.mutate(corpus[parent], corpus);
      if (ex.execute(child)) {
        ++found;
        if (!opt.save_corpus.empty())
          std::ofstream(fs::path(opt.save_corpus) / (target.name + "-" + hex(fnv1a(child))), std::ios::binary) << child;
        corpus.push_back(std::move(child));
      }
    }
  }
  const Counts& c = ex.counts;
  std::cout << "debris_fuzz " << opt.mode << " " << target.name << ": " << c.runs << " inputs (" << c.accepted
            << " accepted, " << c.rejected << " rejected with a named error, " << c.skipped << " skipped"
            << (c.skipped ? ": " + target.skip_reason : std::string()) << "), " << seeds << " seeds, " << found
            << " new corpus entries, " << ex.edges() << " edges, " << elapsed() << " s, no finding\n";
  fs::remove_all(scratch);
  return 0;
}
