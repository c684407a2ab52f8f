// weft-sim built without tools/render (libepoxy or stb missing): no pictures.
#include "sim/pictures.h"

namespace weft::sim {

bool renderer_built_in() { return false; }

std::string PictureRecorder::write(const scenes::Scene&, const scenes::SceneWorld&, bool) const {
    return "this weft-sim was built without the renderer (install libepoxy-dev and libstb-dev, then reconfigure)";
}

}  // namespace weft::sim
