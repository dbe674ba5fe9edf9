// A libFuzzer-free driver for the fuzz targets, for the test suite: it runs
// LLVMFuzzerTestOneInput on every file of a corpus directory, then on `runs`
// mutations of them (bit flips, bytes from a small dictionary of separators
// and digits, insertions, deletions, duplicated and spliced ranges, cuts),
// drawn from a fixed seed so that a failure repeats. Built with any compiler,
// so the smoke runs in the release and ASan+UBSan builds the suite already has
// (the coverage-guided runs are scripts/fuzz.sh's job).
//
//   fuzz_smoke_<target> CORPUS_DIR [RUNS=2000] [SEED=1]
//
// Before each execution the input is written to smoke_input in the target's
// scratch directory (fuzz_input.h; /dev/shm/groundline-fuzz-<pid>/), which a
// sanitizer report or an abort leaves behind, so that it can be replayed.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes ReadBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Bytes that change how a text format splits and reads: separators, signs,
// digits, exponent and special-number letters, YAML/JSON punctuation.
constexpr char kDictionary[] = "\n\r\t ,:;#-+.0123456789eEnaNIf[]{}\"'!&*|>%\0\xff";

void Mutate(std::mt19937_64& rng, const std::vector<Bytes>& corpus, Bytes* input) {
  auto pick = [&rng](std::size_t n) {
    return n == 0 ? 0 : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
  };
  const int mutations = 1 + static_cast<int>(pick(4));
  for (int m = 0; m < mutations; ++m) {
    Bytes& b = *input;
    switch (pick(7)) {
      case 0:  // flip one bit
        if (!b.empty()) b[pick(b.size())] ^= static_cast<std::uint8_t>(1u << pick(8));
        break;
      case 1:  // overwrite a byte from the dictionary
        if (!b.empty()) b[pick(b.size())] = kDictionary[pick(sizeof(kDictionary))];
        break;
      case 2:  // insert a dictionary byte
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(pick(b.size() + 1)),
                 static_cast<std::uint8_t>(kDictionary[pick(sizeof(kDictionary))]));
        break;
      case 3: {  // delete a range
        if (b.empty()) break;
        const std::size_t at = pick(b.size());
        const std::size_t n = std::min(b.size() - at, 1 + pick(16));
        b.erase(b.begin() + static_cast<std::ptrdiff_t>(at),
                b.begin() + static_cast<std::ptrdiff_t>(at + n));
        break;
      }
      case 4: {  // duplicate a range in place
        if (b.empty() || b.size() > (1u << 16)) break;
        const std::size_t at = pick(b.size());
        const std::size_t n = std::min(b.size() - at, 1 + pick(64));
        const Bytes piece(b.begin() + static_cast<std::ptrdiff_t>(at),
                          b.begin() + static_cast<std::ptrdiff_t>(at + n));
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(pick(b.size() + 1)), piece.begin(),
                 piece.end());
        break;
      }
      case 5: {  // splice: a range of another corpus file
        const Bytes& other = corpus[pick(corpus.size())];
        if (other.empty()) break;
        const std::size_t at = pick(other.size());
        const std::size_t n = std::min(other.size() - at, 1 + pick(128));
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(pick(b.size() + 1)),
                 other.begin() + static_cast<std::ptrdiff_t>(at),
                 other.begin() + static_cast<std::ptrdiff_t>(at + n));
        break;
      }
      default:  // cut the end off (a torn file)
        b.resize(pick(b.size() + 1));
        break;
    }
  }
}

void Run(const std::string& input_path, const Bytes& input) {
  {
    std::ofstream out(input_path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(input.data()),
              static_cast<std::streamsize>(input.size()));
  }
  LLVMFuzzerTestOneInput(input.data(), input.size());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 4) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR [RUNS=2000] [SEED=1]\n", argv[0]);
    return 2;
  }
  const std::filesystem::path dir = argv[1];
  const long runs = argc > 2 ? std::strtol(argv[2], nullptr, 10) : 2000;
  const unsigned long seed = argc > 3 ? std::strtoul(argv[3], nullptr, 10) : 1;
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    if (entry.is_regular_file()) files.push_back(entry.path());
  }
  if (ec || files.empty()) {
    std::fprintf(stderr, "%s: no corpus files in %s\n", argv[0], dir.c_str());
    return 2;
  }
  std::sort(files.begin(), files.end());  // the same order, so the same mutations
  std::vector<Bytes> corpus;
  for (const auto& f : files) corpus.push_back(ReadBytes(f));

  const std::string input_path = (groundline::fuzz::ScratchDir() / "smoke_input").string();
  std::printf("%s: each input is written to %s first\n", argv[0], input_path.c_str());
  for (const Bytes& input : corpus) Run(input_path, input);
  std::mt19937_64 rng(seed);
  for (long i = 0; i < runs; ++i) {
    Bytes input = corpus[std::uniform_int_distribution<std::size_t>(0, corpus.size() - 1)(rng)];
    Mutate(rng, corpus, &input);
    Run(input_path, input);
  }
  std::printf("%s: %zu corpus files and %ld mutations, no failure\n", argv[0], corpus.size(), runs);
  return 0;
}
