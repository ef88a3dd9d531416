// What the libFuzzer targets share: a scratch directory to write in, the shipped files, and how a
// bug that is not a crash (an exception silt does not report normally) stops the fuzzer.
#pragma once

#include <string>

namespace silt::fuzz {

// Makes the paths among libFuzzer's arguments absolute (corpora, -artifact_prefix, -dict, ...;
// crash files go to the current directory when no prefix is given), then enters a new temporary
// directory, removed at exit: whatever an input writes stays there. Call from
// LLVMFuzzerInitialize, which runs before libFuzzer reads its arguments.
void enter_scratch_dir(int* argc, char*** argv);

// A file of the source tree ("scenes/pack_2d.toml").
std::string source_path(const std::string& relative);
std::string read_file(const std::string& path);
void write_file(const std::string& path, const std::string& text);

// The memory compile() sees as available (fuzz_machine.cpp stands in for core/machine.cpp): a
// scene larger than this is refused by silt's own check, so that a large but valid scene is a
// SceneError rather than a timeout, and an allocation beyond libFuzzer's limits is a bug.
void set_available_memory(double bytes);

// Prints `what` and aborts: libFuzzer saves the input as a crash.
[[noreturn]] void bug(const std::string& what);

}  // namespace silt::fuzz
