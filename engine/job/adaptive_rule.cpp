#include "engine/job/adaptive_rule.hpp"

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "engine/job/job_error.hpp"
#include "engine/job/toml_table_reader.hpp"

namespace ggk::engine {
namespace {

constexpr std::array<std::string_view, 9> kAdaptiveKeys = {
    "compare", "metrics", "target", "width", "batch", "level", "correction", "method", "range"};
constexpr std::array<std::string_view, 2> kMethodNames = {"bernstein", "asymptotic"};
constexpr std::array<std::string_view, 2> kTargetNames = {"sign", "width"};
constexpr std::array<std::string_view, 2> kCorrectionNames = {"bonferroni", "none"};

// A string or a non-empty array of strings, each element passed to `read`.
template <class Read>
void for_each_text(const TomlTableReader& table, std::string_view key, Read read) {
  const toml::node* node = table.find(key);
  if (node == nullptr) table.fail(key, "required key is missing");
  if (const auto* text = node->as_string()) {
    read(*node, text->get());
    return;
  }
  const auto* array = node->as_array();
  if (array == nullptr || array->empty()) {
    table.fail(key,
               "expected a string or a non-empty array of strings, got " + describe_value(*node));
  }
  for (const toml::node& element : *array) {
    const auto* text = element.as_string();
    if (text == nullptr) {
      table.fail_at(element, key, "expected a string, got " + describe_value(element));
    }
    read(element, text->get());
  }
}

}  // namespace

std::optional<MetricRange> AdaptiveRule::declared_range(std::string_view metric) const {
  for (const MetricRange& range : ranges) {
    if (range.metric == metric) return range;
  }
  return std::nullopt;
}

std::optional<AdaptiveComparison> parse_adaptive_comparison(std::string_view text) {
  const std::size_t equals = text.find('=');
  if (equals == std::string_view::npos || equals == 0) return std::nullopt;
  const std::string_view values = text.substr(equals + 1);
  const std::size_t comma = values.find(',');
  if (comma == std::string_view::npos || comma == 0 || comma + 1 == values.size() ||
      values.find(',', comma + 1) != std::string_view::npos) {
    return std::nullopt;
  }
  AdaptiveComparison comparison{std::string(text.substr(0, equals)),
                                std::string(values.substr(0, comma)),
                                std::string(values.substr(comma + 1))};
  if (comparison.a == comparison.b) return std::nullopt;
  return comparison;
}

std::optional<AdaptiveRule> parse_adaptive_table(const TomlTableReader& job, std::int32_t runs) {
  const std::optional<TomlTableReader> table = job.subtable("adaptive", kAdaptiveKeys);
  if (!table) return std::nullopt;
  AdaptiveRule rule;
  for_each_text(*table, "compare", [&](const toml::node& node, const std::string& text) {
    const std::optional<AdaptiveComparison> comparison = parse_adaptive_comparison(text);
    if (!comparison) {
      table->fail_at(node, "compare",
                     "expected AXIS=A,B (the axis and two of its values, e.g. \"basis=ggk,ogk\"), "
                     "got \"" +
                         shortened(text) + "\"");
    }
    for (const AdaptiveComparison& earlier : rule.comparisons) {
      if (earlier.text() == comparison->text()) {
        table->fail_at(node, "compare", "\"" + shortened(text) + "\" is given twice");
      }
    }
    rule.comparisons.push_back(*comparison);
  });
  for_each_text(*table, "metrics", [&](const toml::node& node, const std::string& metric) {
    if (metric.empty()) table->fail_at(node, "metrics", "a metric's name is empty");
    for (const std::string& earlier : rule.metrics) {
      if (earlier == metric) {
        table->fail_at(node, "metrics", "metric '" + shortened(metric) + "' is given twice");
      }
    }
    rule.metrics.push_back(metric);
  });
  rule.target = table->choice("target", kTargetNames, std::string("sign")) == "sign"
                    ? AdaptiveTarget::kSign
                    : AdaptiveTarget::kWidth;
  if (rule.target == AdaptiveTarget::kWidth) {
    rule.width = table->number("width", NumberRange::above(0.0));
  } else if (table->has("width")) {
    table->fail("width", "a width is a target of its own: give target = \"width\" with it");
  }
  rule.batch = static_cast<std::int32_t>(table->integer("batch", {1, 1000000}, 5));
  if (rule.batch > runs) {
    table->fail("batch", "a batch of " + std::to_string(rule.batch) +
                             " runs is more than the job's runs = " + std::to_string(runs) +
                             " (the most runs a configuration gets)");
  }
  rule.level = table->number("level", NumberRange::open(0.0, 1.0), 0.95);
  rule.correction =
      table->choice("correction", kCorrectionNames, std::string("bonferroni")) == "bonferroni"
          ? AdaptiveCorrection::kBonferroni
          : AdaptiveCorrection::kNone;
  rule.method = table->choice("method", kMethodNames, std::string("bernstein")) == "bernstein"
                    ? AdaptiveMethod::kBernstein
                    : AdaptiveMethod::kAsymptotic;
  if (const toml::node* node = table->find("range")) {
    const auto* ranges = node->as_table();
    if (ranges == nullptr) {
      table->fail("range",
                  "expected a table of METRIC = [LOW, HIGH], got " + describe_value(*node));
    }
    for (const auto& [key, value] : *ranges) {
      const std::string metric(key.str());
      const std::string path = "range." + metric;
      const auto* pair = value.as_array();
      const bool numbers =
          pair != nullptr && pair->size() == 2 && (*pair)[0].is_number() && (*pair)[1].is_number();
      if (!numbers) {
        table->fail_at(value, path,
                       "expected [LOW, HIGH] (two numbers), got " + describe_value(value));
      }
      const double low = (*pair)[0].value<double>().value();
      const double high = (*pair)[1].value<double>().value();
      if (!std::isfinite(low) || !std::isfinite(high) || !(low < high)) {
        table->fail_at(value, path, "expected finite LOW < HIGH, got " + describe_value(value));
      }
      rule.ranges.push_back({metric, low, high});
    }
  }
  return rule;
}

std::optional<AdaptiveRule> adaptive_rule_of_text(const std::string& job_text,
                                                  const std::string& file, std::int32_t runs) {
  toml::table root;
  try {
    root = toml::parse(job_text, file);
  } catch (const toml::parse_error& e) {
    throw JobError(file, location_of(e.source()), "", std::string(e.description()));
  }
  static constexpr std::array<std::string_view, 1> kAdaptiveOnly = {"adaptive"};
  toml::table only;
  if (const toml::node* adaptive = root.get("adaptive")) only.insert("adaptive", *adaptive);
  const TomlTableReader reader(only, "", file, kAdaptiveOnly);
  return parse_adaptive_table(reader, runs);
}

}  // namespace ggk::engine
