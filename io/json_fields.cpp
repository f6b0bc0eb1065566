#include "io/json_fields.h"

#include <cmath>
#include <limits>

#include "core/error.h"

namespace vf {
namespace {

using nlohmann::json;

// What a value is, for a message: "a string", "an array", ...; its text (cut short) follows.
std::string describeJson(const json& v) {
  std::string text = v.dump();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return text + " (" + (v.is_string()    ? "a string"
                        : v.is_array()   ? "an array"
                        : v.is_object()  ? "an object"
                        : v.is_boolean() ? "a boolean"
                        : v.is_null()    ? "null"
                                         : "a number") +
         ")";
}

std::string quoted(const std::string& field) { return "'" + field + "'"; }

}  // namespace

const json& jsonMember(const json& object, const std::string& key, const std::string& field, const std::string& source) {
  if (!object.is_object()) {
    const size_t dot = field.rfind('.');
    const std::string parent = dot == std::string::npos ? std::string("the file") : quoted(field.substr(0, dot));
    throw Error(source + ": " + parent + " must be a JSON object, got " + describeJson(object));
  }
  const auto it = object.find(key);
  if (it == object.end()) throw Error(source + ": no " + quoted(field));
  return *it;
}

double jsonNumber(const json& value, const std::string& field, const std::string& source) {
  if (!value.is_number()) throw Error(source + ": " + quoted(field) + " must be a number, got " + describeJson(value));
  const double v = value.get<double>();
  if (!std::isfinite(v)) throw Error(source + ": " + quoted(field) + " must be a finite number, got " + value.dump());
  return v;
}

float jsonFloat(const json& value, const std::string& field, const std::string& source) {
  const double v = jsonNumber(value, field, source);
  if (std::abs(v) > double(std::numeric_limits<float>::max()))
    throw Error(source + ": " + quoted(field) + " = " + value.dump() + " is beyond a float's range");
  return float(v);
}

int jsonInteger(const json& value, int min, int max, const std::string& field, const std::string& source) {
  const double v = jsonNumber(value, field, source);
  if (v != std::floor(v) || v < min || v > max)
    throw Error(source + ": " + quoted(field) + " must be an integer from " + std::to_string(min) + " to " +
                std::to_string(max) + ", got " + value.dump());
  return int(v);
}

const json& jsonArray(const json& value, long size, const std::string& field, const std::string& source) {
  if (!value.is_array()) throw Error(source + ": " + quoted(field) + " must be an array, got " + describeJson(value));
  if (size >= 0 && long(value.size()) != size)
    throw Error(source + ": " + quoted(field) + " must hold " + std::to_string(size) + " elements, got " +
                std::to_string(value.size()));
  return value;
}

}  // namespace vf
