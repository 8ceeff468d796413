#include "scene/json_cursor.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <cctype>
#include <cmath>
#include <vector>

#include "util/error.h"

namespace wp {

namespace {

// Line and column of a byte of `text`. nlohmann reports the byte after the
// offending token; count lines up to it.
std::string location_of(const std::string& text, size_t byte) {
  size_t end = std::min(byte == 0 ? 0 : byte - 1, text.size());
  int line = 1;
  int column = 1;
  for (size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return std::to_string(line) + ":" + std::to_string(column);
}

// A number too large for a double (nlohmann: "number overflow parsing
// 'TOKEN'"), which the parser reports without a position: the place is
// that of the token's first appearance in the text.
std::string number_out_of_range(const std::string& text, const nlohmann::json::out_of_range& e) {
  const std::string w = e.what();
  const size_t open = w.find('\''), close = w.rfind('\'');
  if (open == std::string::npos || close <= open) return "JSON number out of range (" + w + ")";
  std::string token = w.substr(open + 1, close - open - 1);
  const size_t at = text.find(token);
  if (token.size() > 40) token = token.substr(0, 37) + "...";
  const std::string problem = "JSON number " + token + " is out of the range of double-precision numbers";
  return at == std::string::npos ? problem : location_of(text, at + 1) + ": " + problem;
}

std::string describe(const nlohmann::json::parse_error& e) {
  // what() is "[json.exception.parse_error.101] parse error at line L, column C: MESSAGE".
  std::string w = e.what();
  size_t colon = w.find(": ");
  return colon == std::string::npos ? w : w.substr(colon + 2);
}

}  // namespace

nlohmann::json read_json_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(path + ": cannot open scene file (" + (std::filesystem::exists(path) ? "permission denied" : "no such file") + ")");
  }
  std::stringstream text;
  text << in.rdbuf();
  try {
    return nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path + ":" + location_of(text.str(), e.byte) + ": JSON syntax error: " + describe(e));
  } catch (const nlohmann::json::out_of_range& e) {
    throw InputError(path + ": " + number_out_of_range(text.str(), e));
  }
}

std::string json_type_name(const nlohmann::json& value) {
  return value.type_name();
}

void JsonCursor::fail(const std::string& problem) const {
  throw InputError(file_ + ": at " + (path_.empty() ? std::string("/") : path_) + ": " + problem);
}

JsonCursor JsonCursor::operator[](const char* key) const {
  expect_object();
  auto it = value_.find(key);
  if (it == value_.end()) fail(std::string("missing required key \"") + key + "\"");
  return JsonCursor(*it, path_ + "/" + key, file_);
}

JsonCursor JsonCursor::operator[](size_t index) const {
  expect_array();
  if (index >= value_.size()) fail("expected at least " + std::to_string(index + 1) + " elements");
  return JsonCursor(value_[index], path_ + "/" + std::to_string(index), file_);
}

// Levenshtein distance, case-insensitive: "Radius" and "radus" are both one
// edit from "radius".
static size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t above = row[j];
      bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) == std::tolower(static_cast<unsigned char>(b[j - 1]));
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
  // Close means at most a third of the word's letters changed (two for long
  // words): a typo, not another word.
  const size_t allowed = std::min<size_t>(2, std::max<size_t>(1, word.size() / 3));
  std::string best;
  size_t bestDistance = allowed + 1;
  for (const std::string& c : candidates) {
    size_t d = edit_distance(word, c);
    if (d < bestDistance) {
      bestDistance = d;
      best = c;
    }
  }
  return best.empty() ? "" : " (did you mean \"" + best + "\"?)";
}

void JsonCursor::allow_only(std::initializer_list<const char*> allowed) const {
  allow_only(std::vector<std::string>(allowed.begin(), allowed.end()));
}

void JsonCursor::allow_only(const std::vector<std::string>& allowed) const {
  expect_object();
  for (auto it = value_.begin(); it != value_.end(); ++it) {
    bool known = false;
    for (const std::string& a : allowed) known = known || it.key() == a;
    if (!known) {
      std::string list;
      for (const std::string& a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
      std::string hint = did_you_mean(it.key(), allowed);
      JsonCursor(*it, path_ + "/" + it.key(), file_)
          .fail("unknown key \"" + it.key() + "\"" + (hint.empty() ? " (expected one of: " + list + ")" : hint));
    }
  }
}

JsonCursor JsonCursor::expect_object() const {
  if (!value_.is_object()) fail("expected an object, got " + json_type_name(value_));
  return *this;
}

JsonCursor JsonCursor::expect_array() const {
  if (!value_.is_array()) fail("expected an array, got " + json_type_name(value_));
  return *this;
}

float JsonCursor::number() const {
  if (!value_.is_number()) fail("expected a number, got " + json_type_name(value_));
  double d = value_.get<double>();
  if (!std::isfinite(d) || std::fabs(d) > 3.0e38) fail("number out of range");
  return static_cast<float>(d);
}

float JsonCursor::positive_number() const {
  float v = number();
  if (!(v > 0.0f)) fail("expected a positive number, got " + value_.dump());
  return v;
}

int JsonCursor::integer(int min, int max) const {
  if (!value_.is_number_integer() && !(value_.is_number() && std::floor(value_.get<double>()) == value_.get<double>())) {
    fail("expected an integer, got " + (value_.is_number() ? value_.dump() : json_type_name(value_)));
  }
  double d = value_.get<double>();
  if (d < min || d > max) fail("expected an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "], got " + value_.dump());
  return static_cast<int>(d);
}

std::string JsonCursor::string() const {
  if (!value_.is_string()) fail("expected a string, got " + json_type_name(value_));
  return value_.get<std::string>();
}

bool JsonCursor::boolean() const {
  if (!value_.is_boolean()) fail("expected true or false, got " + json_type_name(value_));
  return value_.get<bool>();
}

glm::vec3 JsonCursor::vec3() const {
  if (value_.is_number()) return glm::vec3(number());
  if (!value_.is_array() || value_.size() != 3) {
    fail("expected a number or an array of 3 numbers, got " +
         (value_.is_array() ? "an array of " + std::to_string(value_.size()) : json_type_name(value_)));
  }
  return glm::vec3((*this)[size_t(0)].number(), (*this)[size_t(1)].number(), (*this)[size_t(2)].number());
}

}  // namespace wp
