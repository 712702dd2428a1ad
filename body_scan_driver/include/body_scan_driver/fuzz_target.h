// Fuzz targets: one per message type our nodes receive and per file reader. Each is written as
//
//   BODY_SCAN_FUZZ_TARGET(pattern_set) { ...use data, size...; return 0; }
//
// The target registers under its name. make fuzz builds one libFuzzer executable per target
// (fuzz_<name>: its source compiled with BODY_SCAN_FUZZ_NAME); in make test, the package's
// test_fuzz_corpus replays fuzz/corpus/<name>/* through every target, so an input that once
// crashed stays fixed.
// A target returns normally on any input its reader rejects with an exception; anything else
// (a crash, a sanitizer report, an abort on a broken invariant) is a finding.
#pragma once

#include <ros/serialization.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <new>
#include <string>
#include <vector>

namespace body_scan_driver::fuzz {

using Entry = int (*)(const uint8_t* data, size_t size);

inline std::map<std::string, Entry>& registeredTargets() {
  static std::map<std::string, Entry> targets;
  return targets;
}

struct Registration {
  Registration(const char* name, Entry entry) { registeredTargets()[name] = entry; }
};

// ROS deserialization of the input as a message (what a subscriber's transport does); false if
// the bytes do not make one. roscpp sizes a vector from its length prefix before reading it, so
// a short input may ask for a huge vector: bad_alloc is a rejection here, as in the transport.
template <typename Message>
bool deserialize(const uint8_t* data, size_t size, Message& message) {
  try {
    ros::serialization::IStream stream(const_cast<uint8_t*>(data), static_cast<uint32_t>(size));
    ros::serialization::deserialize(stream, message);
    return true;
  } catch (const ros::serialization::StreamOverrunException&) {
    return false;
  } catch (const std::bad_alloc&) {
    return false;
  } catch (const std::length_error&) {
    return false;
  }
}

// The input as a file for a reader that takes a path: one file per process and target.
inline std::string inputFile(const char* target, const uint8_t* data, size_t size,
                             const char* extension) {
  const std::string path =
      (std::filesystem::temp_directory_path() /
       ("body_scan_fuzz_" + std::to_string(::getpid()) + "_" + target + extension))
          .string();
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace body_scan_driver::fuzz

#define BODY_SCAN_FUZZ_TARGET(name)                                                            \
  static int name##_fuzz(const uint8_t* data, size_t size);                                    \
  static const ::body_scan_driver::fuzz::Registration name##_registration(#name, name##_fuzz); \
  static int name##_fuzz(const uint8_t* data, size_t size)

// A libFuzzer executable is one fuzz source compiled with BODY_SCAN_FUZZ_NAME="<target>".
#ifdef BODY_SCAN_FUZZ_NAME
// roscpp sizes an array from its 32-bit length prefix before reading it (up to 4 G elements
// from a few bytes), and ASan's operator new aborts where glibc's throws bad_alloc. So that
// finds are ours, not that, new throws bad_alloc above 256 MB (fuzz runs set ASan's
// alloc_dealloc_mismatch=0: these blocks come from malloc).
void* operator new(size_t size) {
  void* block = size <= (size_t{256} << 20) ? std::malloc(size ? size : 1) : nullptr;
  if (!block) throw std::bad_alloc();
  return block;
}
void* operator new[](size_t size) { return operator new(size); }
void operator delete(void* block) noexcept { std::free(block); }
void operator delete[](void* block) noexcept { std::free(block); }
void operator delete(void* block, size_t) noexcept { std::free(block); }
void operator delete[](void* block, size_t) noexcept { std::free(block); }
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const ::body_scan_driver::fuzz::Entry entry =
      ::body_scan_driver::fuzz::registeredTargets().at(BODY_SCAN_FUZZ_NAME);
  return entry(data, size);
}
#endif

namespace body_scan_driver::fuzz {

// Runs every registered target over the files of corpus_root/<name>/; returns the number of
// inputs run per target (a finding aborts). A target without a corpus folder runs 0.
inline std::map<std::string, size_t> replayCorpus(const std::string& corpus_root) {
  std::map<std::string, size_t> runs;
  for (const auto& [name, entry] : registeredTargets()) {
    runs[name] = 0;
    const std::filesystem::path folder = std::filesystem::path(corpus_root) / name;
    if (!std::filesystem::is_directory(folder)) continue;
    for (const auto& file : std::filesystem::directory_iterator(folder)) {
      std::ifstream in(file.path(), std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)),
                              std::istreambuf_iterator<char>());
      entry(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
      ++runs[name];
    }
  }
  return runs;
}

// The seeds of corpus_root/<target>/ that are not one whole serialized `Message` (deserialized,
// no byte left over). A message seed made before the message changed no longer deserializes:
// the target rejects it at once and its replay tests nothing.
template <typename Message>
std::vector<std::string> staleMessageSeeds(const std::string& corpus_root, const char* target) {
  std::vector<std::string> stale;
  const std::filesystem::path folder = std::filesystem::path(corpus_root) / target;
  if (!std::filesystem::is_directory(folder)) return {folder.string() + " (missing)"};
  for (const auto& file : std::filesystem::directory_iterator(folder)) {
    std::ifstream in(file.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    Message message;
    if (!deserialize(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), message) ||
        ros::serialization::serializationLength(message) != bytes.size())
      stale.push_back(file.path().filename().string());
  }
  return stale;
}

}  // namespace body_scan_driver::fuzz
