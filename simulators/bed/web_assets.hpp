// The files of simulators/bed/web/ (the bed view page's script and style,
// and the helpers every page of wearknit shares), built into the library by
// cmake/EmbedAssets.cmake so that a written page needs nothing at run time.
#pragma once

#include <string_view>

namespace bed {

// The text of simulators/bed/web/NAME, or empty when there is no such file.
std::string_view web_asset(std::string_view name);

}  // namespace bed
