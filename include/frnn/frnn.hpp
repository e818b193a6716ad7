// frnn: fast fixed-radius neighbor search. Include this for the whole public API.
#pragma once
#include "frnn/brute_force.hpp"
#include "frnn/buffer.hpp"
#include "frnn/csr.hpp"
#include "frnn/error.hpp"
#include "frnn/grid.hpp"
#include "frnn/grid_geometry.hpp"
#include "frnn/options.hpp"
#include "frnn/parallel.hpp"
#include "frnn/point_sets.hpp"
#include "frnn/search_scale.hpp"
#include "frnn/simd.hpp"
#include "frnn/verlet_lists.hpp"
