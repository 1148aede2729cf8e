// What every libFuzzer target of fly's parsers shares: bad input must end in one of fly's documented errors
// (base/error.h: InputError, exit 3; UsageError, exit 2), and anything else is a finding. A crash, a
// sanitizer report, a hang (-timeout), an allocation over -malloc_limit_mb or a resident size over
// -rss_limit_mb is reported by libFuzzer itself; an exception of any other type is reported here and aborts,
// so that libFuzzer keeps the input as a crash.
#pragma once

#include <unistd.h>
#include <cerrno>
#include <csignal>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <typeinfo>
#include <vector>

#include "base/error.h"
#include "base/log.h"

namespace fly::fuzz {

// The input as text (parsers take any bytes: a binary file must fail cleanly too).
inline std::string_view asText(const uint8_t* data, size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Runs `parse`; returns normally when it succeeds or throws InputError or UsageError, aborts with the
// exception's type and message on anything else.
template <class F>
void expectOnlyInputErrors(F&& parse) {
  try {
    parse();
  } catch (const InputError&) {
  } catch (const UsageError&) {
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz: undocumented exception %s: %s\n", typeid(e).name(), e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "fuzz: undocumented exception of a type not derived from std::exception\n");
    std::abort();
  }
}

// A checked postcondition of a parser's result: a failure is a finding.
inline void require(bool condition, const char* what) {
  if (!condition) {
    std::fprintf(stderr, "fuzz: postcondition failed: %s\n", what);
    std::abort();
  }
}

// Removes the scratch directories (fly-fuzz-PID) in `root` of processes that are gone: libFuzzer ends with
// _Exit after a finding or a single input, which skips the exit handler of scratchDir().
inline void removeStaleScratchDirs(const std::filesystem::path& root) {
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(root, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("fly-fuzz-", 0) != 0) continue;
    const pid_t pid = pid_t(std::atol(name.c_str() + 9));
    if (pid > 0 && kill(pid, 0) != 0 && errno == ESRCH) std::filesystem::remove_all(e.path(), ec);
  }
}

// A private scratch directory on tmpfs (/dev/shm when present), for the parsers that read files; removed at
// exit.
inline const std::filesystem::path& scratchDir() {
  // Never destroyed, so that the exit handler that removes it can still read it.
  static const std::filesystem::path* const dir = [] {
    removeStaleScratchDirs("/dev/shm");
    removeStaleScratchDirs(std::filesystem::temp_directory_path());
    const std::string name = "fly-fuzz-" + std::to_string(getpid());
    auto* d = new std::filesystem::path(std::filesystem::path("/dev/shm") / name);
    std::error_code ec;
    if (!std::filesystem::create_directories(*d, ec)) {  // no tmpfs there, or not writable
      *d = std::filesystem::temp_directory_path() / name;
      std::filesystem::create_directories(*d);
    }
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(scratchDir(), ignored);
    });
    return d;
  }();
  return *dir;
}

// Writes `bytes` to `path` (no atomic rename: the scratch directory is private).
inline void writeScratchFile(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out) {
    std::fprintf(stderr, "fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
}

// Fills `dir` with the files the repository's sample scenes and test scenes refer to (scenes/*/*,
// tests/data/scene_file/*), flat, so that a seed made from one of them finds its buffers, models, IES and
// weather files beside it. The repository's root is FLY_SOURCE_DIR (a compile definition), or the
// environment variable FLY_FUZZ_SOURCE_DIR for targets run from a copy of the tree elsewhere.
inline void copyFixtures(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  fs::create_directories(dir);
  const char* moved = std::getenv("FLY_FUZZ_SOURCE_DIR");
  const fs::path root = moved ? moved : FLY_SOURCE_DIR;
  std::vector<fs::path> folders = {root / "tests/data/scene_file"};
  for (const fs::directory_entry& e : fs::directory_iterator(root / "scenes")) {
    if (e.is_directory()) folders.push_back(e.path());
  }
  for (const fs::path& folder : folders) {
    for (const fs::directory_entry& e : fs::directory_iterator(folder)) {
      if (e.is_regular_file())
        fs::copy_file(e.path(), dir / e.path().filename(), fs::copy_options::overwrite_existing);
    }
  }
}

// A scratch folder `name` holding the fixtures (copyFixtures), made once per process.
inline std::filesystem::path fixtureDir(const std::string& name) {
  const std::filesystem::path dir = scratchDir() / name;
  copyFixtures(dir);
  return dir;
}

// Warnings of the parsers would flood the fuzzer's output: only errors are logged.
inline void quietLog() {
  log::setLevel(log::Level::kError);
}

}  // namespace fly::fuzz
