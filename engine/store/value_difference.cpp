#include "engine/store/value_difference.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

namespace ggk::engine {

namespace {

using ElementClass = Hdf5File::ElementClass;

// The element at `bytes` as a double (exact for every integer below 2^53).
double as_double(const unsigned char* bytes, ElementClass element_class, std::size_t size) {
  const auto read = [bytes]<class T>(T) {
    T value;
    std::memcpy(&value, bytes, sizeof value);
    return static_cast<double>(value);
  };
  switch (element_class) {
    case ElementClass::kFloat:
      return size == sizeof(float) ? read(float{}) : read(double{});
    case ElementClass::kSigned:
      switch (size) {
        case 1:
          return read(std::int8_t{});
        case 2:
          return read(std::int16_t{});
        case 4:
          return read(std::int32_t{});
        default:
          return read(std::int64_t{});
      }
    case ElementClass::kUnsigned:
      switch (size) {
        case 1:
          return read(std::uint8_t{});
        case 2:
          return read(std::uint16_t{});
        case 4:
          return read(std::uint32_t{});
        default:
          return read(std::uint64_t{});
      }
    default:
      return std::numeric_limits<double>::quiet_NaN();
  }
}

bool numeric(ElementClass element_class) {
  return element_class == ElementClass::kFloat || element_class == ElementClass::kSigned ||
         element_class == ElementClass::kUnsigned;
}

// Equal within the tolerance (floats) or identical (everything else); `same_bits`
// says whether the two elements' bytes are identical.
bool within(double a, double b, bool same_bits, ElementClass element_class,
            const Tolerance& tolerance) {
  if (same_bits) return true;
  if (element_class != ElementClass::kFloat) return false;
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  if (std::isinf(a) || std::isinf(b)) return a == b;
  return std::fabs(a - b) <= tolerance.atol + tolerance.rtol * std::fabs(b);
}

std::string number(double value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

// A string element as printed: quoted, newlines as \n, at most 60 characters.
std::string quoted(std::string text) {
  std::string escaped;
  for (const char c : text) escaped += c == '\n' ? std::string("\\n") : std::string(1, c);
  if (escaped.size() > 60) escaped = escaped.substr(0, 57) + "...";
  return "\"" + escaped + "\"";
}

std::string short_number(double value) {
  std::ostringstream out;
  out.precision(2);
  out << value;
  return out.str();
}

}  // namespace

ValuesDifference compare_values(const Hdf5File::Values& a, const Hdf5File::Values& b,
                                const Tolerance& tolerance) {
  ValuesDifference result;
  std::int64_t count = 1;
  for (const std::int64_t extent : a.shape) count *= extent;
  std::size_t byte_offset = 0, string_offset = 0;
  for (std::size_t p = 0; p < a.parts.size() && p < b.parts.size(); ++p) {
    const Hdf5File::Part& part = a.parts[p];
    for (std::int64_t i = 0; i < count; ++i) {
      ++result.elements;
      ElementPlace place;
      place.index = i;
      place.member = part.member;
      bool equal = false;
      if (part.element_class == ElementClass::kString) {
        const std::size_t at = string_offset + static_cast<std::size_t>(i);
        place.is_string = true;
        place.text_a = at < a.strings.size() ? a.strings[at] : "";
        place.text_b = at < b.strings.size() ? b.strings[at] : "";
        equal = place.text_a == place.text_b;
        if (!equal) ++result.bitwise;
      } else {
        const std::size_t at = byte_offset + static_cast<std::size_t>(i) * part.element_size;
        if (at + part.element_size > a.bytes.size() || at + part.element_size > b.bytes.size()) {
          break;  // not the same layout: the caller compared types and shapes first
        }
        const bool same_bits =
            std::memcmp(a.bytes.data() + at, b.bytes.data() + at, part.element_size) == 0;
        place.a = as_double(a.bytes.data() + at, part.element_class, part.element_size);
        place.b = as_double(b.bytes.data() + at, part.element_class, part.element_size);
        equal = within(place.a, place.b, same_bits, part.element_class, tolerance);
        if (!same_bits) {
          ++result.bitwise;
          const double absolute = std::fabs(place.a - place.b);
          if (numeric(part.element_class) && std::isfinite(absolute)) {
            const double relative = place.b == 0.0 ? std::numeric_limits<double>::infinity()
                                                   : absolute / std::fabs(place.b);
            if (!result.absolute_at || absolute > result.largest_absolute) {
              result.largest_absolute = absolute;
              result.absolute_at = place;
            }
            if (!result.relative_at || relative > result.largest_relative) {
              result.largest_relative = relative;
              result.relative_at = place;
            }
          }
        }
      }
      if (!equal) {
        ++result.differing;
        if (!result.first_differing) result.first_differing = place;
      }
    }
    if (part.element_class == ElementClass::kString) {
      string_offset += static_cast<std::size_t>(count);
    } else {
      byte_offset += static_cast<std::size_t>(count) * part.element_size;
    }
  }
  return result;
}

std::string element_place(const ElementPlace& place, const std::vector<std::int64_t>& shape) {
  if (!place.member.empty()) {
    return "row " + std::to_string(place.index) + ", column " + place.member;
  }
  std::vector<std::int64_t> index(shape.size(), 0);
  std::int64_t rest = place.index;
  for (std::size_t d = shape.size(); d-- > 0;) {
    if (shape[d] > 0) {
      index[d] = rest % shape[d];
      rest /= shape[d];
    }
  }
  std::string text = "[";
  for (std::size_t d = 0; d < index.size(); ++d) {
    text += (d == 0 ? "" : ", ") + std::to_string(index[d]);
  }
  return text + "]";
}

std::string describe_difference(const ValuesDifference& difference,
                                const std::vector<std::int64_t>& shape) {
  std::string text = std::to_string(difference.differing) + " of " +
                     std::to_string(difference.elements) + " elements";
  if (difference.absolute_at) {
    const ElementPlace& at = *difference.absolute_at;
    text += "; largest absolute difference " + short_number(difference.largest_absolute) + " at " +
            element_place(at, shape) + " (" + number(at.a) + " vs " + number(at.b) +
            "), largest relative " + short_number(difference.largest_relative) + " at " +
            element_place(*difference.relative_at, shape);
  }
  if (difference.first_differing) {
    const ElementPlace& first = *difference.first_differing;
    if (first.is_string || !difference.absolute_at ||
        !(std::isfinite(first.a) && std::isfinite(first.b))) {
      text += "; first at " + element_place(first, shape) + " (" +
              (first.is_string ? quoted(first.text_a) + " vs " + quoted(first.text_b)
                               : number(first.a) + " vs " + number(first.b)) +
              ")";
    }
  }
  return text;
}

}  // namespace ggk::engine
