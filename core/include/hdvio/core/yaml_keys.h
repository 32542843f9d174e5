#pragma once
// yaml-cpp keeps every entry of a map but answers lookups with the first one, so a repeated key
// would silently win or lose. Every YAML the project reads (experiments, sensor.yaml) goes
// through this check.
#include <string>

namespace YAML {
class Node;
}

namespace hdvio {

// Throws InputError(file, line, ...) naming the repeated key and both lines, at any depth.
void rejectDuplicateYamlKeys(const YAML::Node& node, const std::string& file);

}  // namespace hdvio
