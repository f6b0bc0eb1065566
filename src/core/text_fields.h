#pragma once
// Numbers from text fields, strictly: the whole field is the number, nothing before or after it
// (strtod("12abc") would give 12, std::stoi throws on overflow). Every reader of text files and
// every option parser goes through these.
#include <string>

namespace vf {

// strtod's syntax, "inf" and "nan" included (some formats use them: ScanNet marks a lost pose
// with -inf); false for an empty field or one with anything left over.
bool parseDouble(const std::string& field, double& value);
bool parseFiniteDouble(const std::string& field, double& value);
bool parseFiniteFloat(const std::string& field, float& value);
// A decimal integer within int's range.
bool parseInt(const std::string& field, int& value);

}  // namespace vf
