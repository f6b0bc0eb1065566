#pragma once
// Typed fields of the JSON files datasets keep (Record3D metadata, Replica cam_params.json,
// Open3D camera-intrinsics.json). nlohmann's own type errors ("[json.exception.type_error.302]
// type must be number, but is string") name neither the file nor the field; these do:
// "<source>: 'camera.fx' must be a number, got "600" (a string)".
#include <nlohmann/json.hpp>

#include <string>

namespace vf {

// The member `key` of `object`, or throws "<source>: no '<field>'" (field = the name written out,
// e.g. "camera.w"). Throws "<source>: '<parent>' must be an object" when `object` is not one.
const nlohmann::json& jsonMember(const nlohmann::json& object, const std::string& key, const std::string& field,
                                 const std::string& source);

// A finite number (an integer or a float).
double jsonNumber(const nlohmann::json& value, const std::string& field, const std::string& source);

// A finite number within float's range.
float jsonFloat(const nlohmann::json& value, const std::string& field, const std::string& source);

// An integer in [min, max] (a float with a fraction, or one out of range, is an error).
int jsonInteger(const nlohmann::json& value, int min, int max, const std::string& field, const std::string& source);

// An array of exactly `size` elements when size >= 0, of any size otherwise.
const nlohmann::json& jsonArray(const nlohmann::json& value, long size, const std::string& field,
                                const std::string& source);

}  // namespace vf
