#include "rgbdi/map/map_data.h"

namespace rgbdi::map {

MapView MapView::of(const MapData& map) {
  MapView v;
  v.manifest = map.manifest;
  v.places.reserve(map.places.size());
  for (const loop::LoopKeyframe& p : map.places) v.places.push_back({&p, p.T_world_body});
  v.loops = map.loops;
  v.keyframes.reserve(map.keyframes.size());
  for (const mapping::Keyframe& k : map.keyframes.keyframes()) v.keyframes.push_back(&k);
  return v;
}

MapData MapView::copy() const {
  MapData m;
  m.manifest = manifest;
  m.places.reserve(places.size());
  for (const Place& p : places) {
    m.places.push_back(*p.keyframe);
    m.places.back().T_world_body = p.T_world_body;
  }
  m.loops = loops;
  for (const mapping::Keyframe* k : keyframes) m.keyframes.add(*k);
  return m;
}

}  // namespace rgbdi::map
