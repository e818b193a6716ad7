// The table of solver parameters: one row per key of a scene's "viscoelastic" and "sph"
// sections, with its unit, the range the scene parser accepts, the narrower range a control
// panel offers (tested: 100 steps at either end stay finite), whether a running solver takes a
// change, and a getter and setter on a scene. The scene parser and writer read and write these
// sections through the table, so a parameter added here is parsed, saved and shown in the
// viewer's panel with no other change.
//
// Complexity O(1) per access (the table is built once). Thread safety: the table is immutable;
// get/set touch only the scene passed to them.
#pragma once
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "frnn/sim/scene.hpp"

namespace frnn::sim {

enum class parameter_kind {
    real,     ///< a number
    boolean,  ///< 0 or 1
    choice    ///< an index into `choices`, written in JSON as the choice's name
};

struct parameter {
    std::string section;  ///< the scene's JSON object holding the key: "viscoelastic" or "sph"
    std::string key;      ///< the JSON key inside the section
    std::string unit;     ///< "1" for dimensionless numbers
    std::string help;     ///< one line for tooltips
    parameter_kind kind = parameter_kind::real;
    double min = 0, max = 0;         ///< accepted by the parser (real only)
    double ui_min = 0, ui_max = 0;   ///< a control's range, where the solver stays stable
    bool log_scale = false;          ///< the control moves in powers (spans decades)
    std::vector<std::string> choices;
    /// The running solver takes a change at its next step; otherwise the scene must restart
    /// (the parameter sets the kernel radius, the particle mass or stored per-particle state).
    bool live = true;
    std::function<double(const scene&)> get;
    std::function<void(scene&, double)> set;

    /// "section.key", the name used in messages, scripts and the panel.
    std::string name() const { return section + "." + key; }
    /// The value in a default-constructed scene (the struct's default member values).
    double default_value() const { return get(scene{}); }
};

/// Every solver parameter, in the order of the panel (section, then the scene file's order).
const std::vector<parameter>& parameters();
/// The row named "section.key", or nullptr.
const parameter* find_parameter(std::string_view name);
/// Throws frnn::error naming the parameter when `value` is outside [min, max], or not a whole
/// number for a boolean or a choice.
void check_parameter_value(const parameter& p, double value);
/// The section of a solver's parameters: "viscoelastic" or "sph".
std::string parameter_section(solver_kind k);

}  // namespace frnn::sim
