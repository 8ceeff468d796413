// json_cursor.h — typed, path-aware access to a parsed JSON document. Every
// value knows where it sits (a JSON pointer such as /surfaces/2/radius), so
// errors name the file, the place and the problem in one line.
#pragma once

#include <nlohmann/json.hpp>

#include <glm/glm.hpp>

#include <initializer_list>
#include <string>
#include <vector>

namespace wp {

class JsonCursor {
 public:
  JsonCursor(const nlohmann::json& value, std::string path, const std::string& file)
      : value_(value), path_(std::move(path)), file_(file) {}

  const nlohmann::json& json() const { return value_; }
  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }

  [[noreturn]] void fail(const std::string& problem) const;

  bool has(const char* key) const { return value_.is_object() && value_.contains(key); }
  JsonCursor operator[](const char* key) const;  // required member
  JsonCursor operator[](size_t index) const;     // required element
  size_t size() const { return value_.size(); }

  // Rejects any member not in `allowed`, naming it.
  void allow_only(std::initializer_list<const char*> allowed) const;
  void allow_only(const std::vector<std::string>& allowed) const;

  bool is_object() const { return value_.is_object(); }
  bool is_array() const { return value_.is_array(); }
  bool is_string() const { return value_.is_string(); }
  bool is_number() const { return value_.is_number(); }

  JsonCursor expect_object() const;
  JsonCursor expect_array() const;
  float number() const;
  float positive_number() const;
  int integer(int min, int max) const;
  std::string string() const;
  bool boolean() const;
  glm::vec3 vec3() const;  // [x, y, z] or one number for all three
  glm::vec3 color() const { return vec3(); }

  float number_or(const char* key, float fallback) const { return has(key) ? (*this)[key].number() : fallback; }
  int integer_or(const char* key, int fallback, int min, int max) const {
    return has(key) ? (*this)[key].integer(min, max) : fallback;
  }
  glm::vec3 vec3_or(const char* key, glm::vec3 fallback) const { return has(key) ? (*this)[key].vec3() : fallback; }

 private:
  const nlohmann::json& value_;
  std::string path_;
  const std::string& file_;
};

// The JSON document in file `path`; an InputError names a syntax error's
// line and column.
nlohmann::json read_json_file(const std::string& path);

std::string json_type_name(const nlohmann::json& value);

// " (did you mean \"NAME\"?)" for the candidate a typo away from `word`, or "".
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace wp
