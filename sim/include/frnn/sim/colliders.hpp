// Colliders of the fluid solvers: signed distance functions of oriented planes, spheres and
// oriented boxes, each either an obstacle (fluid outside) or a container (fluid inside), each
// optionally moving along a scripted path (translation, oscillation, rotation about an axis).
//
// phi(x) > 0 in the space the fluid may occupy; a particle closer than a margin is projected
// back along the gradient and its velocity relative to the surface is reflected with a
// restitution coefficient and damped tangentially by a Coulomb-like friction coefficient.
// A container box is resolved by clamping in its own frame, an exact projection with no leak at
// corners. All math is in 3D; 2D scenes use z = 0 (see flatten_to_2d).
//
// Complexity: O(colliders) per particle. Thread safety: const members may run concurrently.
#pragma once
#include <array>
#include <string>
#include <vector>

namespace frnn::sim {

using vec3 = std::array<double, 3>;

/// A scripted path: center(t) = center + velocity t + amplitude sin(2 pi frequency t + phase),
/// orientation angle(t) = angle + angular_velocity t about the collider's axis.
struct motion {
    vec3 velocity{0, 0, 0};
    vec3 amplitude{0, 0, 0};
    double frequency = 0, phase = 0;
    double angular_velocity = 0;  ///< radians per second
};

enum class shape { plane, sphere, box };

struct collider {
    shape kind = shape::plane;
    bool inside = false;  ///< container: the fluid stays inside (box, sphere)
    vec3 center{0, 0, 0};  ///< plane: a point of the plane
    vec3 normal{0, 1, 0};  ///< plane: points into the fluid side
    vec3 half{0.5, 0.5, 0.5};  ///< box half extents
    double radius = 0.5;       ///< sphere
    vec3 axis{0, 0, 1};        ///< rotation axis of the orientation and of the motion
    double angle = 0;          ///< initial rotation (radians) about `axis`
    double restitution = 0, friction = 0;
    motion path;
    std::string name;
};

/// Where the fluid may not go, at one instant: the collider posed at time t.
class posed_collider {
public:
    posed_collider(const collider& c, double t);
    /// Signed distance, positive in the fluid's space; n receives the unit gradient.
    double phi(const vec3& x, vec3& n) const;
    /// Velocity of the collider's material at point x.
    vec3 velocity_at(const vec3& x) const;
    /// Projects x to at least `margin` inside the fluid's space; reflects v. Returns true when
    /// the particle was moved.
    bool resolve(vec3& x, vec3& v, double margin) const;
    /// Calls f(distance, normal) for each planar wall near x (distance < reach): a container box
    /// yields its faces, other shapes their tangent plane. Used by SPH boundary integrals.
    template <class F>
    void for_each_wall(const vec3& x, double reach, F&& f) const;
    const collider& desc() const { return *c_; }
    /// World position of a point given in the collider's own frame (for drawing).
    vec3 to_world(const vec3& local) const {
        const vec3 d = to_world_dir(local);
        return {center_[0] + d[0], center_[1] + d[1], center_[2] + d[2]};
    }

private:
    vec3 to_local(const vec3& x) const;
    vec3 to_world_dir(const vec3& d) const;
    const collider* c_;
    vec3 center_;
    double rot_[3][3];   // local -> world
    vec3 normal_;        // plane normal in world
    vec3 lin_vel_;       // translational velocity of the path at t
    vec3 omega_;         // angular velocity vector
};

template <class F>
void posed_collider::for_each_wall(const vec3& x, double reach, F&& f) const {
    if (c_->kind == shape::box && c_->inside) {
        const vec3 p = to_local(x);
        for (int a = 0; a < 3; ++a) {
            if (c_->half[a] > 1e20) continue;  // flattened axis of a 2D scene
            for (int side = -1; side <= 1; side += 2) {
                const double d = c_->half[a] - side * p[a];
                if (d >= reach) continue;
                vec3 local{0, 0, 0};
                local[a] = -side;
                f(d, to_world_dir(local));
            }
        }
        return;
    }
    vec3 n;
    const double d = phi(x, n);
    if (d < reach) f(d, n);
}

/// The colliders of a scene.
class collider_set {
public:
    collider_set() = default;
    explicit collider_set(std::vector<collider> colliders) : list_(std::move(colliders)) {}
    const std::vector<collider>& list() const { return list_; }
    std::vector<posed_collider> at(double t) const;
    bool empty() const { return list_.empty(); }

private:
    std::vector<collider> list_;
};

/// Makes colliders valid for a 2D scene: z components dropped, rotation about z only, boxes
/// unbounded in z.
void flatten_to_2d(collider& c);

}  // namespace frnn::sim
