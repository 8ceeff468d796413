#include "scene/json_cursor.h"

#include <cmath>

#include "util/error.h"

namespace wp {

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

void JsonCursor::allow_only(std::initializer_list<const char*> allowed) const {
  expect_object();
  for (auto it = value_.begin(); it != value_.end(); ++it) {
    bool known = false;
    for (const char* a : allowed) known = known || it.key() == a;
    if (!known) {
      std::string list;
      for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
      JsonCursor(*it, path_ + "/" + it.key(), file_).fail("unknown key \"" + it.key() + "\" (expected one of: " + list + ")");
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

glm::vec3 JsonCursor::vec3() const {
  if (value_.is_number()) return glm::vec3(number());
  if (!value_.is_array() || value_.size() != 3) {
    fail("expected a number or an array of 3 numbers, got " +
         (value_.is_array() ? "an array of " + std::to_string(value_.size()) : json_type_name(value_)));
  }
  return glm::vec3((*this)[size_t(0)].number(), (*this)[size_t(1)].number(), (*this)[size_t(2)].number());
}

}  // namespace wp
