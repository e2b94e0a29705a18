#include "gather_core/figures/palette.hpp"

namespace gather {
namespace figures {

const std::vector<Rgb>& segment_palette() {
  static const std::vector<Rgb> p = {
      {67, 99, 216},   {60, 180, 75},   {255, 225, 25},  {245, 130, 49}, {145, 30, 180},  {66, 212, 244},
      {240, 50, 230},  {191, 239, 69},  {250, 190, 212}, {70, 153, 144}, {220, 190, 255}, {154, 99, 36},
      {170, 255, 195}, {128, 128, 0},   {255, 216, 177}, {255, 250, 200}};
  return p;
}

const std::vector<Rgb>& collector_palette() {
  static const std::vector<Rgb> p = {
      {30, 100, 200}, {240, 130, 20}, {40, 150, 40},  {150, 50, 150}, {150, 80, 40},
      {0, 150, 150},  {220, 40, 180}, {140, 140, 0},  {40, 40, 130},  {200, 60, 60}};
  return p;
}

}  // namespace figures
}  // namespace gather
