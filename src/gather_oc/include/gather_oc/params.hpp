#pragma once
// Private parameters read with their type checked: roscpp's param() quietly
// falls back to the default when a value has another type (_cycles:=abc), so
// a wrong value would go unnoticed.
#include <ros/ros.h>

#include <string>

namespace gather {

// Reads ~name into `value` (`fallback` when unset). Returns "" or one line
// saying what is wrong ("~cycles must be an integer").
template <typename T>
std::string typed_param(const ros::NodeHandle& pnh, const std::string& name, T& value, const T& fallback) {
  if (!pnh.hasParam(name)) {
    value = fallback;
    return "";
  }
  if (pnh.getParam(name, value)) return "";
  const char* type = std::is_same<T, bool>::value     ? "true or false"
                     : std::is_same<T, int>::value    ? "an integer"
                     : std::is_same<T, double>::value ? "a number"
                                                      : "a string";
  return "~" + name + " must be " + type;
}

}  // namespace gather
