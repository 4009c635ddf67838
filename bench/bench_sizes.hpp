#pragma once
// "2,1,0.5" (element sizes in mm) -> {2e-3, 1e-3, 0.5e-3} m: the benches'
// size lists (fit_load_bench, fit_resolution_bench).
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

inline std::vector<double> ParseSizesMm(const std::string& text) {
  std::vector<double> out;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) out.push_back(std::atof(item.c_str()) * 1e-3);
  return out;
}
