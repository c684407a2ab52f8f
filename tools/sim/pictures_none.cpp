// weft-sim built without the renderer (libepoxy missing): no pictures; --gltf still works.
#include "sim/pictures.h"

namespace weft::sim {

bool renderer_built_in() { return false; }

std::string PictureRecorder::draw(const scenes::Scene&, render::Snapshot, bool) const {
    return "this weft-sim was built without the renderer (install libepoxy-dev, then reconfigure)";
}

}  // namespace weft::sim
