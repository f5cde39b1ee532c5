// The files of planner/viewer/web/ (the plan page's script), built into the
// library by cmake/EmbedAssets.cmake.
#pragma once

#include <string_view>

namespace planner::viewer {

// The text of planner/viewer/web/NAME, or empty when there is no such file.
std::string_view web_asset(std::string_view name);

}  // namespace planner::viewer
