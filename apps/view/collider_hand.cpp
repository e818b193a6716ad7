#include "collider_hand.hpp"

namespace frnn::view {

sim::collider collider_hand::follow(sim::collider c, double t) {
    const sim::vec3 at = c.center;
    if (!holding_ || t < from_time_) {  // a new grab, or the scene restarted under the hand
        holding_ = true;
        from_ = at, from_time_ = t;
        velocity_ = {0, 0, 0};
    } else if (t > from_time_) {
        // Frames with no step in between add up their displacements into the next velocity.
        for (int a = 0; a < 3; ++a) velocity_[a] = (at[a] - from_[a]) / (t - from_time_);
        from_ = at, from_time_ = t;
    }
    // center(t') = at + velocity (t' - t) + the scripted path's own terms.
    for (int a = 0; a < 3; ++a) {
        c.center[a] = at[a] - velocity_[a] * t;
        c.path.velocity[a] += velocity_[a];
    }
    return c;
}

}  // namespace frnn::view
