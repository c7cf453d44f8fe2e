// The fuzz targets' main in the ordinary build, which has no libFuzzer: it replays
// every file of the target's corpus (each one named valid-* must be accepted), then
// runs a fixed number of inputs mutated from the corpus with a fixed seed (bit
// flips, insertions, deletions, truncations, splices, repeated chunks, boundary
// numbers), so the test suite runs each parser over its corpus and a short
// deterministic fuzz run. A finding ends the process; the input it was on is left
// in ./<target>.crash.
//   <target> CORPUS_DIR [--inputs N] [--seed S] [--max-len BYTES]
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;

struct Options {
  fs::path corpus;
  long inputs = 2000;
  std::uint64_t seed = 1;
  std::size_t max_len = 16384;
};

// splitmix64: the same numbers with every compiler and library.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t Next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  std::size_t Below(std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(Next() % n); }

 private:
  std::uint64_t state_;
};

// Text the parsers treat specially: numbers at the edges, separators, YAML syntax.
constexpr std::string_view kTokens[] = {
    "0", "-1", "1e308", "-1e308", "1e-320", "nan", "inf", "-0", "4294967296", "9223372036854775807",
    "-9223372036854775808", "0.000000001", "4000000000", "\n", "\r\n", " ", "\t", ",", "#", ".", "-",
    std::string_view("\0", 1), ": ", "{", "[", "- ", "&a ", "*a", "!!binary ", "\"", "'", "\n@@\n"};

std::string g_input;       // the input being run, for the crash file
std::string g_crash_file;  // <target>.crash

extern "C" void OnCrash(int sig) {
  const int fd = open(g_crash_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd >= 0) {
    [[maybe_unused]] const ssize_t n = write(fd, g_input.data(), g_input.size());
    close(fd);
  }
  static const char kMessage[] = "fuzz: the input that ended the run is in the .crash file\n";
  [[maybe_unused]] const ssize_t n = write(2, kMessage, sizeof kMessage - 1);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void Run(const std::string& input) {
  g_input = input;
  LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(g_input.data()), g_input.size());
}

void Overwrite(std::string& s, std::size_t at, Rng& rng) {
  static constexpr std::uint64_t kValues[] = {0, ~0ULL, 0x7fffffffULL, 0x80000000ULL, 0x7fffffffffffffffULL, 1, 0xffff};
  const std::size_t width = std::size_t{1} << rng.Below(4);
  const std::uint64_t value = rng.Below(3) == 0 ? rng.Next() : kValues[rng.Below(std::size(kValues))];
  for (std::size_t i = 0; i < width && at + i < s.size(); ++i) s[at + i] = static_cast<char>(value >> (8 * i));
}

void Mutate(std::string& s, Rng& rng, const std::vector<std::string>& corpus) {
  const std::size_t at = rng.Below(s.size() + 1);
  switch (rng.Below(8)) {
    case 0:
      if (!s.empty()) s[rng.Below(s.size())] ^= static_cast<char>(1 << rng.Below(8));
      break;
    case 1:
      s.insert(at, 1, static_cast<char>(rng.Next()));
      break;
    case 2:
      s.erase(at, 1 + rng.Below(16));
      break;
    case 3:
      s.resize(rng.Below(s.size() + 1));
      break;
    case 4: {
      const std::string& other = corpus[rng.Below(corpus.size())];
      s = s.substr(0, at) + other.substr(rng.Below(other.size() + 1));
      break;
    }
    case 5: {
      const std::string chunk = s.substr(rng.Below(s.size() + 1), 1 + rng.Below(64));
      for (std::size_t n = 1 + rng.Below(8); n > 0; --n) s.insert(at, chunk);
      break;
    }
    case 6:
      s.replace(at, rng.Below(8), kTokens[rng.Below(std::size(kTokens))]);
      break;
    default:
      Overwrite(s, at, rng);
  }
}

Options ParseOptions(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--inputs" && has_value) {
      o.inputs = std::stol(argv[++i]);
    } else if (arg == "--seed" && has_value) {
      o.seed = std::stoull(argv[++i]);
    } else if (arg == "--max-len" && has_value) {
      o.max_len = std::stoul(argv[++i]);
    } else if (o.corpus.empty() && arg.rfind("--", 0) != 0) {
      o.corpus = arg;
    } else {
      std::fprintf(stderr, "usage: %s CORPUS_DIR [--inputs N] [--seed S] [--max-len BYTES]\n", argv[0]);
      std::exit(2);
    }
  }
  if (o.corpus.empty()) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR [--inputs N] [--seed S] [--max-len BYTES]\n", argv[0]);
    std::exit(2);
  }
  return o;
}

std::vector<std::pair<fs::path, std::string>> ReadCorpus(const fs::path& dir) {
  std::vector<std::pair<fs::path, std::string>> files;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    files.emplace_back(entry.path(), std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()));
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Every corpus file once; returns how many valid-* files were refused.
int Replay(const std::vector<std::pair<fs::path, std::string>>& files) {
  int refused = 0;
  for (const auto& [path, bytes] : files) {
    Run(bytes);
    if (path.filename().string().rfind("valid", 0) == 0 && !sgslam::fuzz::LastInputAccepted()) {
      std::fprintf(stderr, "corpus file %s should be accepted, but: %s\n", path.c_str(),
                   sgslam::fuzz::LastRefusal().c_str());
      ++refused;
    }
  }
  return refused;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = ParseOptions(argc, argv);
  const auto files = ReadCorpus(o.corpus);
  if (files.empty()) {
    std::fprintf(stderr, "no corpus files in %s\n", o.corpus.c_str());
    return 1;
  }
  g_crash_file = fs::path(argv[0]).filename().string() + ".crash";
  for (const int sig : {SIGSEGV, SIGABRT, SIGFPE, SIGBUS, SIGILL}) std::signal(sig, OnCrash);
  const auto start = std::chrono::steady_clock::now();
  const int refused = Replay(files);
  std::vector<std::string> corpus;
  for (const auto& f : files) corpus.push_back(f.second);
  Rng rng(o.seed);
  long accepted = 0;
  for (long i = 0; i < o.inputs; ++i) {
    std::string s = corpus[rng.Below(corpus.size())];
    for (std::size_t m = 1 + rng.Below(4); m > 0; --m) Mutate(s, rng, corpus);
    if (s.size() > o.max_len) s.resize(o.max_len);
    Run(s);
    accepted += sgslam::fuzz::LastInputAccepted() ? 1 : 0;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s: %zu corpus files (%d valid-* refused), %ld mutated inputs (%ld accepted), %.2f s\n",
              o.corpus.filename().c_str(), files.size(), refused, o.inputs, accepted, seconds);
  return refused == 0 ? 0 : 1;
}
