#pragma once
// Typed, unit-checked reading of one TOML table with line numbers in every
// error (private to bf_io: the scene file and the campaign manifest share it).
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "bridgefit/core/error.hpp"
#include "bridgefit/core/input_limits.hpp"
#include "bridgefit/core/units.hpp"

namespace bridgefit::io::detail {

// A TOML file's text, read within the text-size limit; binary data is
// refused naming the file (`what`: "scene file", "campaign manifest").
inline std::string ReadTomlText(const std::filesystem::path& path, const std::string& what) {
  std::string text = ReadFileLimited(path, InputLimits::FromEnvironment().max_text_bytes,
                                     InputLimits::kTextBytesVariable, what);
  if (text.find('\0') != std::string::npos)
    throw Error(ErrorKind::kInput, "the " + what + " is not text (binary data)",
                {.file = path.string(), .expected = "a TOML text file"});
  return text;
}

inline int LineOf(const toml::node& node) { return static_cast<int>(node.source().begin.line); }

// One TOML table (a [section], or an element of an [[array]]) with the keys it
// allows; every getter names the file, the line and the key in its errors.
class Section {
 public:
  Section(const toml::table& root, const std::string& file, const char* name,
          std::set<std::string> allowed)
      : file_(file), name_(name) {
    const toml::node* node = root.get(name);
    if (!node) return;
    table_ = node->as_table();
    if (!table_)
      throw Error(ErrorKind::kInput, "must be a [section] table",
                  {.file = file_, .line = LineOf(*node), .field = name_});
    CheckKeys(allowed);
  }
  // A table that is not a key of a root (an element of an array of tables);
  // `name` is how messages call it, e.g. "specimen[2]".
  Section(const toml::table* table, const std::string& file, const std::string& name,
          const std::set<std::string>& allowed)
      : file_(file), name_(name), table_(table) {
    CheckKeys(allowed);
  }

  bool present() const { return table_ != nullptr; }
  bool has(const char* key) const { return table_ && table_->get(key); }
  int line() const { return table_ ? LineOf(*table_) : 0; }
  const std::string& name() const { return name_; }
  const std::string& file() const { return file_; }

 private:
  void CheckKeys(const std::set<std::string>& allowed) const {
    if (!table_) return;
    for (auto&& [key, value] : *table_) {
      const std::string k(key.str());
      if (!allowed.count(k)) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        throw Error(ErrorKind::kInput, "unknown key",
                    {.file = file_, .line = LineOf(value), .field = name_ + "." + k,
                     .expected = "one of " + list});
      }
    }
  }

 public:
  ErrorContext Context(const char* key, const std::string& expected = "") const {
    const toml::node* node = table_ ? table_->get(key) : nullptr;
    return {.file = file_, .line = node ? LineOf(*node) : line(), .field = name_ + "." + key,
            .expected = expected};
  }

  [[noreturn]] void Missing(const char* key, const std::string& expected) const {
    throw Error(ErrorKind::kInput, "missing required key",
                {.file = file_, .line = line(), .field = name_ + "." + key, .expected = expected});
  }

  // A dimensional value written as a string with a unit, e.g. "12.7 mm".
  double Quantity(const char* key, const Dimension& dimension) const {
    const toml::node* node = table_ ? table_->get(key) : nullptr;
    if (!node) Missing(key, DescribeDimension(dimension));
    if (node->is_number()) {
      const double v = node->value<double>().value_or(0.0);
      if (dimension == Dimension::None()) return v;
      throw Error(ErrorKind::kInput, "a bare number needs a unit",
                  {.file = file_, .line = LineOf(*node), .field = name_ + "." + key,
                   .value = fmt::format("{:g}", v),
                   .expected = DescribeDimension(dimension) + " (a quoted string)"});
    }
    const auto text = node->value<std::string>();
    if (!text)
      throw Error(ErrorKind::kInput, "wrong value type",
                  {.file = file_, .line = LineOf(*node), .field = name_ + "." + key,
                   .expected = DescribeDimension(dimension)});
    try {
      return ParseQuantity(*text, dimension);
    } catch (const Error& e) {
      throw e.WithContext(Context(key));
    }
  }

  std::optional<double> OptionalQuantity(const char* key, const Dimension& dimension) const {
    if (!has(key)) return std::nullopt;
    return Quantity(key, dimension);
  }

  double Number(const char* key, double fallback, bool required = false) const {
    const toml::node* node = table_ ? table_->get(key) : nullptr;
    if (!node) {
      if (required) Missing(key, "a number");
      return fallback;
    }
    const auto v = node->value<double>();
    if (!v)
      throw Error(ErrorKind::kInput, "must be a plain number",
                  {.file = file_, .line = LineOf(*node), .field = name_ + "." + key,
                   .expected = "a number such as 0.3"});
    return *v;
  }

  std::string String(const char* key, const std::string& fallback, bool required = false) const {
    const toml::node* node = table_ ? table_->get(key) : nullptr;
    if (!node) {
      if (required) Missing(key, "a string");
      return fallback;
    }
    const auto v = node->value<std::string>();
    if (!v)
      throw Error(ErrorKind::kInput, "must be a string",
                  {.file = file_, .line = LineOf(*node), .field = name_ + "." + key,
                   .expected = "a quoted string"});
    return *v;
  }

  bool Bool(const char* key, bool fallback) const {
    const toml::node* node = table_ ? table_->get(key) : nullptr;
    if (!node) return fallback;
    const auto v = node->value<bool>();
    if (!v)
      throw Error(ErrorKind::kInput, "must be true or false",
                  {.file = file_, .line = LineOf(*node), .field = name_ + "." + key,
                   .expected = "true or false"});
    return *v;
  }

  std::vector<double> Numbers(const char* key, size_t count) const {
    const toml::node* node = table_ ? table_->get(key) : nullptr;
    const toml::array* array = node ? node->as_array() : nullptr;
    const std::string expected = fmt::format("an array of {} numbers", count);
    if (!array || array->size() != count)
      throw Error(ErrorKind::kInput, "wrong value",
                  {.file = file_, .line = node ? LineOf(*node) : line(),
                   .field = name_ + "." + key, .expected = expected});
    std::vector<double> out;
    for (const auto& element : *array) {
      const auto v = element.value<double>();
      if (!v)
        throw Error(ErrorKind::kInput, "not a number",
                    {.file = file_, .line = LineOf(element), .field = name_ + "." + key,
                     .expected = expected});
      out.push_back(*v);
    }
    return out;
  }

  // An array of strings (possibly empty: the caller decides what an empty
  // list means).
  std::vector<std::string> Strings(const char* key) const {
    const toml::node* node = table_ ? table_->get(key) : nullptr;
    const toml::array* array = node ? node->as_array() : nullptr;
    const std::string expected = "an array of strings, e.g. [\"a\", \"b\"]";
    if (!array)
      throw Error(ErrorKind::kInput, "wrong value",
                  {.file = file_, .line = node ? LineOf(*node) : line(),
                   .field = name_ + "." + key, .expected = expected});
    std::vector<std::string> out;
    for (const auto& element : *array) {
      const auto v = element.value<std::string>();
      if (!v)
        throw Error(ErrorKind::kInput, "not a string",
                    {.file = file_, .line = LineOf(element), .field = name_ + "." + key,
                     .expected = expected});
      out.push_back(*v);
    }
    return out;
  }

 private:
  std::string file_;
  std::string name_;
  const toml::table* table_ = nullptr;
};

}  // namespace bridgefit::io::detail
