// A collider held by the hand: the viewer sends where the dragged collider is each frame, and
// the simulation thread turns that into a velocity the solvers' boundary handling sees (the
// scripted-motion velocity of frnn/sim/colliders.hpp): its displacement since the last
// position sent at an earlier simulated time, divided by the simulated time of the steps in
// between. Until the next position the collider moves on at that velocity, so a steady drag
// is a smooth motion, not a jump per frame, and a hand at rest stops it after one more frame.
// Thread safety: none; the simulation thread owns it.
#pragma once
#include "frnn/sim/colliders.hpp"

namespace frnn::view {

class collider_hand {
public:
    /// The collider `c` (its center where the hand has it now, at simulated time t) as the
    /// solver should see it: passing through that center at time t with the hand's velocity
    /// added to its scripted motion.
    sim::collider follow(sim::collider c, double t);
    /// Let go: the next follow starts from rest.
    void release() { holding_ = false; }
    const sim::vec3& velocity() const { return velocity_; }

private:
    bool holding_ = false;
    sim::vec3 from_{0, 0, 0};  // the last center sent at an earlier time, and that time
    double from_time_ = 0;
    sim::vec3 velocity_{0, 0, 0};
};

}  // namespace frnn::view
