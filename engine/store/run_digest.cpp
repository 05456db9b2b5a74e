#include "engine/store/run_digest.hpp"

#include <cstring>
#include <optional>
#include <stdexcept>
#include <vector>

namespace ggk::engine {

namespace {

constexpr int kMaxDigestDepth = 32;

// FNV-1a, 64 bits (Fowler, Noll, Vo): a stable, well-known hash; the digest
// finds damage, it does not resist an adversary.
class Fnv1a {
 public:
  void add(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      hash_ ^= bytes[i];
      hash_ *= 0x100000001b3ULL;
    }
  }
  void add(const std::string& text) {
    add(text.data(), text.size());
    add("\0", 1);  // "ab" + "c" differs from "a" + "bc"
  }
  void add(std::int64_t value) { add(&value, sizeof value); }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

bool left_out(const std::string& relative, const std::string& name) {
  if (name == "fit_seconds") return true;  // wall clock
  return relative.empty() &&
         (name == "complete" || name == kRunDigestAttribute || name == kMetadataDigestAttribute);
}

// Hashes `object` (at `relative` below the digest's group) and everything below
// it, each object opened once through its open parent.
void add_object(const Hdf5File::Object& object, const std::string& relative, int depth,
                DigestScope scope, Fnv1a& hash) {
  if (depth > kMaxDigestDepth) throw std::runtime_error(object.path() + ": groups nested too deep");
  hash.add(relative);
  for (const std::string& name : object.attribute_names()) {  // sorted by name
    if (left_out(relative, name)) continue;
    const Hdf5File::Values values = object.read_attribute_values(name);
    hash.add(name);
    hash.add(values.type);
    for (const std::int64_t extent : values.shape) hash.add(extent);
    hash.add(static_cast<std::int64_t>(values.bytes.size()));
    hash.add(values.bytes.data(), values.bytes.size());
    for (const std::string& text : values.strings) hash.add(text);
  }
  switch (object.kind()) {
    case Hdf5File::ObjectKind::kDataset: {
      hash.add("dataset");
      for (const std::int64_t extent : object.dataset_shape()) hash.add(extent);
      if (scope == DigestScope::kContent) {
        static const std::string kWallClock[] = {"fit_seconds"};  // a table's column
        const Hdf5File::Values values = object.read_values(kWallClock);
        hash.add(values.type);
        hash.add(static_cast<std::int64_t>(values.bytes.size()));
        hash.add(values.bytes.data(), values.bytes.size());
        for (const std::string& text : values.strings) hash.add(text);
      }
      return;
    }
    case Hdf5File::ObjectKind::kGroup: {
      hash.add("group");
      for (const std::string& member : object.member_names()) {  // sorted by name
        const std::optional<Hdf5File::Object> child = object.hard_member(member);
        if (!child) throw std::runtime_error(object.path() + "/" + member + ": not a hard link");
        add_object(*child, relative + "/" + member, depth + 1, scope, hash);
      }
      return;
    }
    case Hdf5File::ObjectKind::kOther:
      hash.add("other");
      return;
  }
}

}  // namespace

std::uint64_t run_digest(const Hdf5File& file, const std::string& group, DigestScope scope) {
  Fnv1a hash;
  const std::optional<Hdf5File::Object> object = file.open_hard_link(group);
  if (!object) throw std::runtime_error(group + ": not a hard link");
  add_object(*object, "", 0, scope, hash);
  return hash.value();
}

}  // namespace ggk::engine
