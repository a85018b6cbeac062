// SPDX-License-Identifier: GPL-3.0-or-later
// Runs a fuzz harness over saved inputs without libFuzzer: ctest replays the corpus in
// Testing/Fuzz/corpus/<harness> (the crashers found, and seeds) with every build, sanitized or not.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace fs = std::filesystem;

static void runFile(const fs::path& p)
{
  std::ifstream in(p, std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::fprintf(stderr, "replay %s (%zu bytes)\n", p.string().c_str(), bytes.size());
  LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
}

int main(int argc, char** argv)
{
  size_t n = 0;
  for (int i = 1; i < argc; ++i)
  {
    const fs::path arg(argv[i]);
    if (fs::is_directory(arg))
    {
      std::vector<fs::path> files;
      for (const auto& e : fs::directory_iterator(arg))
        if (e.is_regular_file())
          files.push_back(e.path());
      std::sort(files.begin(), files.end());
      for (const auto& f : files)
        runFile(f), ++n;
    }
    else if (fs::is_regular_file(arg))
      runFile(arg), ++n;
    else
    {
      std::fprintf(stderr, "%s: no such file or folder\n", argv[i]);
      return 1;
    }
  }
  std::printf("replayed %zu input(s) without a finding\n", n);
  return n > 0 ? 0 : 1;
}
