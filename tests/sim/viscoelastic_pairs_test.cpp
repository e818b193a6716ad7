// The viscoelastic pair kernels (sim/src/viscoelastic_pairs.hpp): on random particles with
// neighbor lists of every length modulo 8, coincident pairs and pairs beyond h, open and
// periodic, the base level agrees with a direct double-precision sum of the formulas, and the
// AVX2 level (where the CPU has it) gives the base level's bits.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "frnn/simd.hpp"
#include "viscoelastic_pairs.hpp"

using namespace frnn::sim::detail;

namespace {

constexpr float h = 0.1f;

template <int D>
struct cloud {
    std::vector<float> x, v, p, near;
    std::vector<std::uint32_t> indices;
    std::vector<std::size_t> offsets{0};
    float box[D] = {};
    bool periodic = false;

    explicit cloud(bool periodic_box) : periodic(periodic_box) {
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> unit(0, 1), around(-1, 1);
        const std::size_t n = 400;
        const float side = D == 2 ? 0.6f : 0.3f;
        for (std::size_t i = 0; i < n * D; ++i) x.push_back(side * unit(rng)), v.push_back(around(rng));
        for (int a = 0; a < D; ++a) box[a] = periodic && a != 1 ? side : 0;  // axis 1 stays open
        // Particle 1 sits on particle 0: a pair at distance 0.
        for (int a = 0; a < D; ++a) x[D + a] = x[a];
        for (std::size_t i = 0; i < n; ++i) p.push_back(around(rng)), near.push_back(unit(rng));
        // Lists of everything within 1.2 h, so some listed pairs lie beyond h.
        for (std::size_t i = 0; i < n; ++i) {
            for (std::size_t j = 0; j < n; ++j)
                if (j != i && distance(i, j) < 1.2 * h) indices.push_back(std::uint32_t(j));
            offsets.push_back(indices.size());
        }
    }
    double offset(std::size_t i, std::size_t j, int a) const {
        double r = double(x[j * D + a]) - x[i * D + a];
        if (box[a] > 0) r -= box[a] * std::nearbyint(r / box[a]);
        return r;
    }
    double distance(std::size_t i, std::size_t j) const {
        double d2 = 0;
        for (int a = 0; a < D; ++a) d2 += offset(i, j, a) * offset(i, j, a);
        return std::sqrt(d2);
    }
    std::size_t size() const { return offsets.size() - 1; }
    pair_view view() const { return {x.data(), v.data(), p.data(), near.data(), periodic ? box : nullptr, h}; }
    pair_row row(std::size_t i) const { return {i, indices.data() + offsets[i], indices.data() + offsets[i + 1]}; }
};

const viscosity_coefficients coefficients{0.004f, 0.3f, 0.2f};

// The formulas of viscoelastic.cpp, summed in double.
template <int D>
void reference(const cloud<D>& c, std::size_t i, double* dv, double* rho, double* dx) {
    for (int a = 0; a < D; ++a) dv[a] = dx[a] = 0;
    rho[0] = rho[1] = 0;
    for (std::size_t k = c.offsets[i]; k < c.offsets[i + 1]; ++k) {
        const std::size_t j = c.indices[k];
        const double len = c.distance(i, j), q = len / h;
        if (q >= 1) continue;
        rho[0] += (1 - q) * (1 - q);
        rho[1] += (1 - q) * (1 - q) * (1 - q);
        if (len <= 0) continue;
        double u = 0;
        for (int a = 0; a < D; ++a) u += (double(c.v[i * D + a]) - c.v[j * D + a]) * c.offset(i, j, a) / len;
        u = std::max(0.0, u);
        const double imp = 0.5 * coefficients.dt * (1 - q) * (coefficients.sigma * u + coefficients.beta * u * u) / len;
        const double mag = 0.5 * h * ((double(c.p[i]) + c.p[j]) * (1 - q) + (double(c.near[i]) + c.near[j]) * (1 - q) * (1 - q)) / len;
        for (int a = 0; a < D; ++a) dv[a] -= imp * c.offset(i, j, a), dx[a] -= mag * c.offset(i, j, a);
    }
}

struct results {
    std::vector<float> dv, rho, dx;
};

template <int D>
results run(const viscoelastic_pair_kernels<D>& k, const cloud<D>& c) {
    results r;
    r.dv.resize(c.size() * D), r.dx.resize(c.size() * D), r.rho.resize(c.size() * 2);
    for (std::size_t i = 0; i < c.size(); ++i) {
        k.viscosity(c.view(), c.row(i), coefficients, &r.dv[i * D]);
        k.density(c.view(), c.row(i), &r.rho[i * 2], &r.rho[i * 2 + 1]);
        k.displacement(c.view(), c.row(i), &r.dx[i * D]);
    }
    return r;
}

template <int D>
void check(bool periodic) {
    const cloud<D> c(periodic);
    // Every list length modulo 8 occurs, so every partial block is exercised.
    std::vector<bool> remainders(8);
    for (std::size_t i = 0; i < c.size(); ++i) remainders[(c.offsets[i + 1] - c.offsets[i]) % 8] = true;
    for (bool seen : remainders) ASSERT_TRUE(seen);

    const results base = run<D>(viscoelastic_pairs_for<D>("base"), c);
    std::size_t moved = 0;
    for (std::size_t i = 0; i < c.size(); ++i) {
        double dv[D], rho[2], dx[D];
        reference(c, i, dv, rho, dx);
        for (int a = 0; a < D; ++a) {
            EXPECT_NEAR(base.dv[i * D + a], dv[a], 1e-5 + 1e-4 * std::abs(dv[a])) << "particle " << i;
            EXPECT_NEAR(base.dx[i * D + a], dx[a], 1e-6 + 1e-4 * std::abs(dx[a])) << "particle " << i;
            moved += dv[a] != 0;
        }
        EXPECT_NEAR(base.rho[i * 2], rho[0], 1e-4 * (1 + rho[0])) << "particle " << i;
        EXPECT_NEAR(base.rho[i * 2 + 1], rho[1], 1e-4 * (1 + rho[1])) << "particle " << i;
    }
    EXPECT_GT(moved, c.size() / 2);  // the viscosity acted: the comparison is not of zeros
    // The coincident pair counts in the density (q = 0), not in the forces.
    EXPECT_GE(base.rho[0], 1.f);

    if (!frnn::simd_supported("avx2")) GTEST_SKIP() << "no AVX2 on this CPU";
    const results avx2 = run<D>(viscoelastic_pairs_for<D>("avx2"), c);
    EXPECT_EQ(std::memcmp(base.dv.data(), avx2.dv.data(), base.dv.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(base.rho.data(), avx2.rho.data(), base.rho.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(base.dx.data(), avx2.dx.data(), base.dx.size() * sizeof(float)), 0);
}

}  // namespace

TEST(SimViscoelasticPairs, MatchTheFormulasAndGiveTheSameBitsOnEveryLevel2D) { check<2>(false); }
TEST(SimViscoelasticPairs, MatchTheFormulasAndGiveTheSameBitsOnEveryLevel3D) { check<3>(false); }
TEST(SimViscoelasticPairs, PeriodicBoxTakesTheMinimumImage2D) { check<2>(true); }
TEST(SimViscoelasticPairs, PeriodicBoxTakesTheMinimumImage3D) { check<3>(true); }
