// A main for compilers without libFuzzer (g++): feeds every file named on the
// command line, or found in a named directory, to LLVMFuzzerTestOneInput, so
// the targets build and run their corpora as tests (after simdjson's
// fuzz/main.cpp). A target with a custom mutator also gets a few mutations of
// each input, so the mutator runs too. Fails when no input was found.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
extern "C" __attribute__((weak)) std::size_t LLVMFuzzerCustomMutator(std::uint8_t* data, std::size_t size,
                                                                     std::size_t max_size, unsigned int seed);

// Stand-in for libFuzzer's byte-level mutator, which the custom mutators call:
// flips one bit.
extern "C" std::size_t LLVMFuzzerMutate(std::uint8_t* data, std::size_t size, std::size_t max_size) {
  if (size == 0 || max_size == 0) return 0;
  data[(size * 7 + 3) % size] ^= static_cast<std::uint8_t>(1u << (size % 8));
  return size;
}

namespace fs = std::filesystem;

static void run_file(const fs::path& p, std::size_t& count) {
  std::ifstream in(p, std::ios::binary);
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
  ++count;
  if (!LLVMFuzzerCustomMutator) return;
  constexpr std::size_t kMaxSize = 4096;
  for (unsigned seed = 1; seed <= 8; ++seed) {
    std::vector<std::uint8_t> m = bytes;
    m.resize(kMaxSize);
    m.resize(LLVMFuzzerCustomMutator(m.data(), std::min(bytes.size(), kMaxSize), kMaxSize, seed));
    LLVMFuzzerTestOneInput(m.data(), m.size());
  }
}

int main(int argc, char** argv) {
  std::size_t count = 0;
  for (int i = 1; i < argc; ++i) {
    const fs::path arg = argv[i];
    if (fs::is_directory(arg)) {
      for (const auto& e : fs::recursive_directory_iterator(arg))
        if (e.is_regular_file() && e.path().filename().string()[0] != '.') run_file(e.path(), count);
    } else if (fs::is_regular_file(arg)) {
      run_file(arg, count);
    }
  }
  std::printf("replayed %zu inputs%s\n", count, LLVMFuzzerCustomMutator ? " (and 8 mutations of each)" : "");
  return count > 0 ? 0 : 1;
}
