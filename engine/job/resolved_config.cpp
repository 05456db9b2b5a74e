#include "engine/job/resolved_config.hpp"

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <toml++/toml.h>

namespace ggk::engine {

std::string canonical_integer(std::int64_t value) {
  return std::to_string(value);
}

std::string canonical_number(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text(buffer, result.ptr);
  if (text.find_first_of(".eninf") == std::string::npos) text += ".0";
  return text;
}

std::string canonical_string(std::string_view value) {
  std::string quoted = "\"";
  for (const char c : value) {
    switch (c) {
      case '"':
        quoted += "\\\"";
        break;
      case '\\':
        quoted += "\\\\";
        break;
      case '\n':
        quoted += "\\n";
        break;
      case '\t':
        quoted += "\\t";
        break;
      case '\r':
        quoted += "\\r";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
          char escape[8];
          std::snprintf(escape, sizeof escape, "\\u%04X", static_cast<unsigned char>(c));
          quoted += escape;
        } else {
          quoted += c;
        }
    }
  }
  return quoted + "\"";
}

std::string canonical_boolean(bool value) {
  return value ? "true" : "false";
}

void ResolvedConfig::record(const std::string& key, std::string value, bool given) {
  values_.try_emplace(key, Entry{std::move(value), given});
}

void ResolvedConfig::replace(const std::string& key, std::string value, bool given) {
  values_.insert_or_assign(key, Entry{std::move(value), given});
}

std::optional<std::string> ResolvedConfig::value(const std::string& key) const {
  const auto it = values_.find(key);
  if (it == values_.end()) return std::nullopt;
  return it->second.value;
}

std::set<std::string> ResolvedConfig::given_keys() const {
  std::set<std::string> keys;
  for (const auto& [key, entry] : values_) {
    if (entry.given) keys.insert(key);
  }
  return keys;
}

void ResolvedConfig::mark_unused(const std::string& key, std::string why) {
  unused_[key] = std::move(why);
}

std::optional<std::string> ResolvedConfig::unused_reason(const std::string& key) const {
  const auto found = unused_.find(key);
  if (found == unused_.end()) return std::nullopt;
  return found->second;
}

std::vector<std::string> ResolvedConfig::keys() const {
  std::vector<std::string> keys;
  keys.reserve(values_.size());
  for (const auto& [key, entry] : values_) keys.push_back(key);
  return keys;
}

std::string ResolvedConfig::text() const {
  std::string text;
  for (const auto& [key, entry] : values_) {
    text += canonical_string(key) + " = " + entry.value + "\n";
  }
  return text;
}

std::optional<ResolvedConfig> ResolvedConfig::from_text(std::string_view text) {
  ResolvedConfig config;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    if (end == std::string_view::npos) return std::nullopt;  // every line ends in '\n'
    const std::string_view line = text.substr(0, end);
    text.remove_prefix(end + 1);
    // "key" = value, the key in canonical_string's quotes.
    if (line.size() < 2 || line[0] != '"') return std::nullopt;
    std::string key;
    std::size_t i = 1;
    for (; i < line.size() && line[i] != '"'; ++i) {
      if (line[i] != '\\') {
        key += line[i];
        continue;
      }
      if (++i >= line.size()) return std::nullopt;
      switch (line[i]) {
        case 'n':
          key += '\n';
          break;
        case 't':
          key += '\t';
          break;
        case 'r':
          key += '\r';
          break;
        case '"':
        case '\\':
          key += line[i];
          break;
        default:
          return std::nullopt;  // keys with other escapes are not written by text()
      }
    }
    if (i >= line.size() || line.substr(i + 1, 3) != " = ") return std::nullopt;
    const std::string_view value = line.substr(i + 4);
    if (value.empty() || config.contains(key)) return std::nullopt;
    config.values_.emplace(key, Entry{std::string(value), true});
  }
  return config;
}

std::optional<std::string> ResolvedConfig::difference(const ResolvedConfig& other,
                                                      std::string_view this_label,
                                                      std::string_view other_label,
                                                      const std::set<std::string>& ignored) const {
  const std::vector<std::string> found = differences(other, this_label, other_label, ignored, 1);
  if (found.empty()) return std::nullopt;
  return found.front();
}

std::vector<std::string> ResolvedConfig::differences(const ResolvedConfig& other,
                                                     std::string_view this_label,
                                                     std::string_view other_label,
                                                     const std::set<std::string>& ignored,
                                                     std::size_t limit) const {
  std::vector<std::string> found;
  constexpr std::size_t kShown = 60;
  const auto shown = [](const std::string& value) {
    return value.size() > kShown ? value.substr(0, kShown) + "..." : value;
  };
  // A key as a person knows it: the internal "study.axes" is the study's axes.
  const auto named = [](const std::string& key) {
    return key == "study.axes" ? std::string("the study's axes ([sweep] keys and --sweep options)")
                               : key;
  };
  // Walk both sorted maps together: the first key (in sorted order) that differs.
  auto a = values_.begin();
  auto b = other.values_.begin();
  while (a != values_.end() || b != other.values_.end()) {
    if (a != values_.end() && ignored.count(a->first) > 0) {
      ++a;
      continue;
    }
    if (b != other.values_.end() && ignored.count(b->first) > 0) {
      ++b;
      continue;
    }
    if (b == other.values_.end() || (a != values_.end() && a->first < b->first)) {
      found.push_back(named(a->first) + ": only in " + std::string(this_label));
      if (found.size() >= limit) return found;
      ++a;
      continue;
    }
    if (a == values_.end() || b->first < a->first) {
      // A key that `other` holds at its default (not given) and `this` lacks is
      // no difference: `this` was written before the key existed, and a new
      // key's default is the behaviour from before it (lspi.ridge = "absolute").
      if (!b->second.given) {
        ++b;
        continue;
      }
      found.push_back(named(b->first) + ": only in " + std::string(other_label));
      if (found.size() >= limit) return found;
      ++b;
      continue;
    }
    if (a->second.value != b->second.value) {
      found.push_back(named(a->first) + ": " + shown(a->second.value) + " in " +
                      std::string(this_label) + ", " + shown(b->second.value) + " in " +
                      std::string(other_label));
      if (found.size() >= limit) return found;
    }
    ++a;
    ++b;
  }
  return found;
}

bool ResolvedConfig::operator==(const ResolvedConfig& other) const {
  return !difference(other, "", "").has_value();
}

std::optional<std::vector<std::string>> canonical_elements(std::string_view text) {
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + std::string(text));
  } catch (const toml::parse_error&) {
    return std::nullopt;
  }
  const toml::array* array = parsed.get_as<toml::array>("v");
  if (array == nullptr) return std::nullopt;
  std::vector<std::string> elements;
  for (const toml::node& node : *array) {
    if (const auto* integer = node.as_integer()) {
      elements.push_back(canonical_integer(integer->get()));
    } else if (const auto* number = node.as_floating_point()) {
      elements.push_back(canonical_number(number->get()));
    } else if (const auto* string = node.as_string()) {
      elements.push_back(canonical_string(string->get()));
    } else if (const auto* boolean = node.as_boolean()) {
      elements.push_back(canonical_boolean(boolean->get()));
    } else {
      return std::nullopt;
    }
  }
  return elements;
}

bool same_value_text(const std::string& stored, const std::string& given) {
  if (stored == given) return true;
  char* end_stored = nullptr;
  char* end_given = nullptr;
  const double x = std::strtod(stored.c_str(), &end_stored);
  const double y = std::strtod(given.c_str(), &end_given);
  return !stored.empty() && !given.empty() && *end_stored == '\0' && *end_given == '\0' && x == y;
}

}  // namespace ggk::engine
