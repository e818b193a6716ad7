// One simulation over several ranks (frnn/sim/ranks.hpp), with the one-process result bit for
// bit. Each rank owns the particles in a slab of the one-process grid's cell planes along one
// axis, and holds copies (ghosts) of the particles in the `reach` planes on each side of it.
//
// Why the neighbor rows come out the same: the one-process arrays are in cell order, and a
// cell's particles keep the previous step's order (the grid's counting sort is stable). So each
// particle carries its key in that order, (its cell's slot, its rank inside the cell), and a
// rank sorts its particles and ghosts by key before its grid sorts them by cell: each owned
// particle's row then lists the particles of the one-process row in the same order. A cell
// lies wholly on one rank, whose grid numbers its particles for the next step's keys.
#pragma once
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "frnn/grid.hpp"
#include "frnn/sim/ranks.hpp"

namespace frnn::sim::detail {

/// A per-particle float array that travels with the particles: `components` values each.
struct carried_field {
    std::vector<float>* data;
    std::size_t components;
};

/// A particle's place in the one-process order of the last grid build.
struct order_key {
    std::uint64_t cell = 0;  ///< the cell's slot
    std::uint32_t rank = 0;  ///< its rank among the cell's particles
    bool operator<(const order_key& o) const { return cell != o.cell ? cell < o.cell : rank < o.rank; }
};

template <int D>
class distribution {
    using clock = std::chrono::steady_clock;
    /// Adds the seconds from its making to its end to `into`.
    struct span_timer {
        double& into;
        clock::time_point start = clock::now();
        ~span_timer() { into += std::chrono::duration<double>(clock::now() - start).count(); }
    };

public:
    distribution(std::shared_ptr<rank_comm> comm, const balance_options& balance)
        : comm_(std::move(comm)), balance_(balance) {}

    rank_comm& comm() { return *comm_; }
    /// Ghosts within `depth` times the search's reach: 2 when wall particles take their
    /// pressure from the fluid within one radius of them, up to two radii from a particle.
    void set_halo_depth(int depth) { depth_ = depth; }
    /// Called on every rank when the cut is about to move, with the old cut still in place.
    void before_rebalance(std::function<void()> f) { before_rebalance_ = std::move(f); }
    bool ghost(std::size_t s) const { return ghost_[s] != 0; }
    /// Whether the particles are shared out (the first step's redistribute() did).
    bool started() const { return !bounds_.empty(); }
    std::size_t owned() const { return owned_; }
    std::size_t ghosts() const { return ghost_.size() - owned_; }
    const order_key& key(std::size_t s) const { return key_[s]; }

    /// Before the grid is built: drops last step's ghosts, moves every particle to the rank that
    /// owns its cell plane, adds this step's ghosts and sorts everything by key. fields[0] is
    /// the position. On the first call every rank holds every particle, in the order of the
    /// one-process arrays (the seeding's, or a checkpoint's).
    void redistribute(const grid_geometry<float>& g, const std::vector<carried_field>& fields,
                      std::vector<std::uint32_t>& id) {
        start_step();
        span_timer timed{step_exchange_};
        fields_ = fields;
        const std::size_t n = id.size();
        const bool first = bounds_.empty();
        if (first) start(g, n);
        else if (balance_.check_every > 0 && ++steps_ % balance_.check_every == 0) check_balance(g, n);
        const int me = comm_->rank(), ranks = comm_->size();
        const std::size_t count = std::size_t(ranks);
        std::vector<rank_bytes> moving(count);
        std::vector<std::size_t> staying;
        departures_.clear();
        for (std::size_t i = 0; i < n; ++i) {
            if (!first && ghost_[i]) continue;
            const int q = owner(plane(g, i));
            if (q == me) staying.push_back(i);
            else if (!first) pack(moving[std::size_t(q)], i, id), departures_.emplace_back(id[i], q);  // on the first call q has it too
        }
        // Arrivals and ghosts are appended to the arrays (after the n slots of last step), and
        // one permutation then takes the slots kept, in key order, into this step's arrays.
        std::vector<rank_bytes> arrived = exchange(moving);
        const std::size_t stayed = staying.size();
        for (const rank_bytes& b : arrived) unpack(b, id, 0);
        std::vector<std::uint32_t> owned(staying.begin(), staying.end());
        for (std::size_t i = n; i < id.size(); ++i) owned.push_back(std::uint32_t(i));
        owned_ = owned.size();
        // Ghosts: this rank's particles within reach of another rank's slab.
        std::vector<rank_bytes> copies(count);
        std::vector<std::vector<std::uint32_t>> sent(count);
        for (std::uint32_t i : owned) {
            const std::int64_t c = plane(g, i);
            for (int q = 0; q < ranks; ++q)
                if (q != me && near(q, c, g.reach * depth_)) pack(copies[std::size_t(q)], i, id), sent[std::size_t(q)].push_back(i);
        }
        std::vector<rank_bytes> received = exchange(copies);
        std::vector<std::vector<std::uint32_t>> got(count);
        for (int q = 0; q < ranks; ++q) {
            const std::size_t before = id.size();
            unpack(received[std::size_t(q)], id, 1);
            for (std::size_t i = before; i < id.size(); ++i) got[std::size_t(q)].push_back(std::uint32_t(i));
        }
        // The one-process order of the last step (the grid's sort keeps it inside each cell).
        // The particles that stayed are in it already: the others are sorted and merged in.
        std::vector<std::uint32_t> order(stayed + id.size() - n);
        std::copy(owned.begin(), owned.begin() + std::ptrdiff_t(stayed), order.begin());
        std::iota(order.begin() + std::ptrdiff_t(stayed), order.end(), std::uint32_t(n));
        const auto before = [&](std::uint32_t a, std::uint32_t b) { return key_[a] < key_[b]; };
        const auto arrivals = order.begin() + std::ptrdiff_t(stayed);
        if (!std::is_sorted(order.begin(), arrivals, before)) std::sort(order.begin(), arrivals, before);
        std::sort(arrivals, order.end(), before);
        std::inplace_merge(order.begin(), arrivals, order.end(), before);
        slots_before_ = id.size();
        permute(order, id);
        tag_ = std::move(order);  // tag_[s]: the slot before this sort, for the exchange lists
        sent_ = std::move(sent);
        got_ = std::move(got);
    }

    /// After the grid sorted the arrays (reorder() applied to ghost()): each particle's key for
    /// the next step, and where the ghost exchanges read and write.
    void sorted(const grid<float, D>& grid, const std::vector<float>& x) {
        const grid_geometry<float>& g = grid.geometry();
        const std::span<const std::uint32_t> perm = grid.sorted_to_original();
        const std::size_t n = ghost_.size();
        std::vector<std::uint32_t> slot_of(slots_before_);
        for (std::size_t s = 0; s < n; ++s) slot_of[tag_[perm[s]]] = std::uint32_t(s);
        for (auto* lists : {&sent_, &got_})
            for (auto& list : *lists)
                for (auto& i : list) i = slot_of[i];
        std::uint64_t previous = 0;
        std::uint32_t in_cell = 0;
        for (std::size_t s = 0; s < n; ++s) {
            std::array<float, D> p;
            for (int a = 0; a < D; ++a) p[std::size_t(a)] = x[s * D + std::size_t(a)] * g.scale;
            const std::uint64_t cell = g.slot_of_cell(g.cell_of(p));
            in_cell = s > 0 && cell == previous ? in_cell + 1 : 0;
            previous = cell;
            key_[s] = {cell, in_cell};  // a ghost's is not used
        }
    }

    /// Permutes this class's per-particle flags as the grid permuted the caller's arrays.
    void reorder(const grid<float, D>& grid) { grid.reorder(std::span<std::uint8_t>(ghost_)); }

    /// Each ghost takes its owner's values of these arrays (one value per particle).
    void refresh(std::initializer_list<std::vector<float>*> arrays) {
        std::vector<carried_field> fields;
        for (auto* a : arrays) fields.push_back({a, 1});
        refresh(fields);
    }
    /// The same for arrays of `components` values per particle.
    void refresh(const std::vector<carried_field>& fields) {
        span_timer timed{step_exchange_};
        const std::size_t ranks = std::size_t(comm_->size());
        std::size_t floats = 0;
        for (const auto& f : fields) floats += f.components;
        std::vector<rank_bytes> out(ranks);
        for (std::size_t q = 0; q < ranks; ++q)
            for (std::uint32_t s : sent_[q])
                for (const auto& f : fields)
                    for (std::size_t c = 0; c < f.components; ++c) append(out[q], (*f.data)[s * f.components + c]);
        const std::vector<rank_bytes> in = exchange(out);
        for (std::size_t q = 0; q < ranks; ++q) {
            const char* at = in[q].data();
            if (in[q].size() != got_[q].size() * floats * sizeof(float))
                throw error("ranks: ghost refresh from rank " + std::to_string(q) + " has the wrong size");
            for (std::uint32_t s : got_[q])
                for (const auto& f : fields)
                    for (std::size_t c = 0; c < f.components; ++c)
                        std::memcpy(&(*f.data)[s * f.components + c], at, sizeof(float)), at += sizeof(float);
        }
    }

    /// The ids of the particles the last redistribute() sent to other ranks, and where to.
    const std::vector<std::pair<std::uint32_t, int>>& departures() const { return departures_; }

    /// The rank whose slab holds point x (D floats).
    int owner_of(const grid_geometry<float>& g, const float* x) const {
        std::array<float, D> p;
        for (int a = 0; a < D; ++a) p[std::size_t(a)] = x[a] * g.scale;
        return owner(g.cell_of(p)[std::size_t(axis_)]);
    }

    /// Every rank's particles, ghosts and bytes sent, and the balance checks so far.
    ranks_report report() {
        ranks_report r;
        const double steps = double(std::max<std::uint64_t>(timed_steps_, 1));
        ranks_report::rank mine{owned_, ghosts(), bytes_sent_, 1e3 * exchange_seconds_ / steps, 1e3 * wait_seconds_ / steps,
                                1e3 * (step_seconds_ - exchange_seconds_) / steps};
        for (const rank_bytes& b : comm_->all_gather(bytes_of(mine))) r.per_rank.push_back(value_of<ranks_report::rank>(b));
        r.checks = checks_;
        r.rebalances = rebalances_;
        r.largest_imbalance = largest_imbalance_;
        r.mean_imbalance = checks_ ? imbalance_sum_ / double(checks_) : 0;
        return r;
    }

    /// The largest of every rank's v.
    double max(double v) {
        span_timer timed{step_exchange_};
        double m = v;
        for (const rank_bytes& b : all_gather(bytes_of(v))) m = std::max(m, value_of<double>(b));
        return m;
    }

    /// The message of the particle first in the one-process order among those that ranks
    /// found (found: this rank's first, or none), on every rank; empty when none found one.
    std::string first_found(const order_key* found, const std::string& message) {
        span_timer timed{step_exchange_};
        rank_bytes mine;
        if (found) append(mine, *found), mine.insert(mine.end(), message.begin(), message.end());
        std::string best;
        order_key best_key;
        bool any = false;
        for (const rank_bytes& b : all_gather(mine)) {
            if (b.empty()) continue;
            const order_key k = value_of<order_key>(b);
            if (!any || k < best_key) best_key = k, best = std::string(b.begin() + sizeof(order_key), b.end()), any = true;
        }
        return best;
    }

    /// The owned particles of every rank on rank 0, in the one-process order: the fields given
    /// (one float array each, `components` values per particle) and the ids. Empty on others.
    void gather(const std::vector<carried_field>& fields, const std::vector<std::uint32_t>& id,
                std::vector<std::vector<float>>& out, std::vector<std::uint32_t>& out_id) {
        span_timer timed{step_output_};
        rank_bytes mine;
        for (std::size_t s = 0; s < ghost_.size(); ++s) {
            if (ghost_[s]) continue;
            append(mine, key_[s]);
            append(mine, id[s]);
            for (const auto& f : fields)
                for (std::size_t c = 0; c < f.components; ++c) append(mine, (*f.data)[s * f.components + c]);
        }
        std::size_t floats = 0;
        for (const auto& f : fields) floats += f.components;
        const std::size_t record = sizeof(order_key) + sizeof(std::uint32_t) + floats * sizeof(float);
        struct row {
            order_key key;
            std::size_t at;
        };
        rank_bytes all;
        for (const rank_bytes& b : comm_->gather(mine)) all.insert(all.end(), b.begin(), b.end());
        const std::size_t n = all.size() / record;
        std::vector<row> rows(n);
        for (std::size_t r = 0; r < n; ++r) rows[r] = {value_of<order_key>(all, r * record), r * record};
        std::sort(rows.begin(), rows.end(), [](const row& a, const row& b) { return a.key < b.key; });
        out.assign(fields.size(), {});
        for (std::size_t f = 0; f < fields.size(); ++f) out[f].resize(n * fields[f].components);
        out_id.resize(n);
        for (std::size_t r = 0; r < n; ++r) {
            std::size_t at = rows[r].at + sizeof(order_key);
            out_id[r] = value_of<std::uint32_t>(all, at);
            at += sizeof(std::uint32_t);
            for (std::size_t f = 0; f < fields.size(); ++f)
                for (std::size_t c = 0; c < fields[f].components; ++c)
                    out[f][r * fields[f].components + c] = value_of<float>(all, at), at += sizeof(float);
        }
    }

    /// The owned particles of every rank moved to the rank whose share of the ids holds theirs
    /// (rank q of P: [total q / P, total (q + 1) / P)), in any order: the fields given (one
    /// float array each, `components` values per particle) and the ids.
    void share_by_id(const std::vector<carried_field>& fields, const std::vector<std::uint32_t>& id, std::size_t total,
                     std::vector<std::vector<float>>& out, std::vector<std::uint32_t>& out_id) {
        span_timer timed{step_output_};
        const std::size_t ranks = std::size_t(comm_->size());
        std::vector<rank_bytes> send(ranks);
        for (std::size_t s = 0; s < ghost_.size(); ++s) {
            if (ghost_[s]) continue;
            std::size_t q = std::min(ranks - 1, std::size_t(std::uint64_t(id[s]) * ranks / std::max<std::size_t>(total, 1)));
            while (q > 0 && total * q / ranks > id[s]) --q;
            while (q + 1 < ranks && total * (q + 1) / ranks <= id[s]) ++q;
            append(send[q], id[s]);
            for (const auto& f : fields)
                for (std::size_t c = 0; c < f.components; ++c) append(send[q], (*f.data)[s * f.components + c]);
        }
        std::size_t floats = 0;
        for (const auto& f : fields) floats += f.components;
        const std::size_t record = sizeof(std::uint32_t) + floats * sizeof(float);
        out.assign(fields.size(), {});
        out_id.clear();
        for (const rank_bytes& b : comm_->exchange(send)) {
            if (b.size() % record) throw error("ranks: a frame message of " + std::to_string(b.size()) + " bytes");
            for (std::size_t at = 0; at < b.size();) {
                out_id.push_back(value_of<std::uint32_t>(b, at)), at += sizeof(std::uint32_t);
                for (std::size_t f = 0; f < fields.size(); ++f)
                    for (std::size_t c = 0; c < fields[f].components; ++c) out[f].push_back(value_of<float>(b, at)), at += sizeof(float);
            }
        }
    }

private:
    template <class U>
    static void append(rank_bytes& b, const U& v) {
        const char* p = reinterpret_cast<const char*>(&v);
        b.insert(b.end(), p, p + sizeof(U));
    }
    template <class U>
    static rank_bytes bytes_of(const U& v) {
        rank_bytes b;
        append(b, v);
        return b;
    }
    template <class U>
    static U value_of(const rank_bytes& b, std::size_t at = 0) {
        if (at + sizeof(U) > b.size()) throw error("ranks: a message is shorter than its contents");
        U v;
        std::memcpy(&v, b.data() + at, sizeof(U));
        return v;
    }

    /// The first cut, from every particle (each rank holds them all on the first call).
    void start(const grid_geometry<float>& g, std::size_t n) {
        ghost_.assign(n, 0);
        key_.resize(n);
        // The arrays' order: the seeding's, or a checkpoint's (the one-process order then).
        for (std::size_t i = 0; i < n; ++i) key_[i] = {0, std::uint32_t(i)};
        axis_ = -1;
        set_cut(g, choose_cut(g, histograms(g, n)));
    }

    /// Particles per cell plane along each axis, this rank's (ghosts left out), axis after axis.
    std::vector<std::uint64_t> histograms(const grid_geometry<float>& g, std::size_t n) const {
        std::size_t size = 0;
        for (int a = 0; a < D; ++a) size += std::size_t(g.dims[std::size_t(a)]);
        std::vector<std::uint64_t> count(size, 0);
        for (std::size_t i = 0; i < n; ++i) {
            if (!ghost_.empty() && ghost_[i]) continue;
            const cell_index c = cell(g, i);
            std::size_t at = 0;
            for (int a = 0; a < D; ++a) ++count[at + std::size_t(c[std::size_t(a)])], at += std::size_t(g.dims[std::size_t(a)]);
        }
        return count;
    }

    struct cut_choice {
        int axis = 0;
        std::vector<std::int64_t> bounds;  ///< rank q owns planes [bounds[q], bounds[q + 1])
        std::uint64_t most = 0;            ///< the most particles a rank gets
    };
    /// Along each axis, slabs of about equal counts; the axis whose most loaded rank holds the
    /// fewest (ties: the current axis, then the one with more planes).
    cut_choice choose_cut(const grid_geometry<float>& g, const std::vector<std::uint64_t>& count) const {
        cut_choice best;
        std::size_t at = 0;
        for (int a = 0; a < D; ++a) {
            const std::size_t planes = std::size_t(g.dims[std::size_t(a)]);
            cut_choice c;
            c.axis = a;
            c.bounds = cut(std::vector<std::uint64_t>(count.begin() + std::ptrdiff_t(at), count.begin() + std::ptrdiff_t(at + planes)));
            for (std::size_t q = 0; q + 1 < c.bounds.size(); ++q) {
                std::uint64_t held = 0;
                for (std::int64_t p = c.bounds[q]; p < c.bounds[q + 1]; ++p) held += count[at + std::size_t(p)];
                c.most = std::max(c.most, held);
            }
            at += planes;
            const bool better = a == 0 || c.most < best.most ||
                                (c.most == best.most && (a == axis_ || (best.axis != axis_ && g.dims[std::size_t(a)] > g.dims[std::size_t(best.axis)])));
            if (better) best = std::move(c);
        }
        return best;
    }
    void set_cut(const grid_geometry<float>& g, cut_choice c) {
        axis_ = c.axis;
        bounds_ = std::move(c.bounds);
        wraps_ = g.wraps[std::size_t(axis_)];
        planes_ = g.dims[std::size_t(axis_)];
    }

    /// Slabs of about equal particle counts, from the count in each plane.
    std::vector<std::int64_t> cut(const std::vector<std::uint64_t>& count) const {
        const std::uint64_t ranks = std::uint64_t(comm_->size());
        const std::int64_t planes = std::int64_t(count.size());
        std::uint64_t n = 0;
        for (std::uint64_t c : count) n += c;
        std::vector<std::int64_t> bounds(ranks + 1, planes);
        bounds[0] = 0;
        std::uint64_t below = 0, r = 1;
        for (std::int64_t c = 0; c < planes && r < ranks; ++c) {
            while (r < ranks && below * ranks >= r * n) bounds[r++] = c;
            below += count[std::size_t(c)];
        }
        return bounds;
    }

    /// The most loaded rank against the mean; a new cut when it exceeds 1 + imbalance.
    void check_balance(const grid_geometry<float>& g, std::size_t n) {
        std::vector<std::uint64_t> count = histograms(g, n);
        std::uint64_t mine = 0;
        for (std::size_t i = 0; i < n; ++i) mine += ghost_[i] ? 0 : 1;
        std::uint64_t most = 0, total = 0;
        for (const rank_bytes& b : all_gather(bytes_of(mine))) {
            const std::uint64_t k = value_of<std::uint64_t>(b);
            most = std::max(most, k), total += k;
        }
        const double imbalance = total ? double(most) * double(comm_->size()) / double(total) : 1;
        ++checks_;
        imbalance_sum_ += imbalance;
        largest_imbalance_ = std::max(largest_imbalance_, imbalance);
        if (imbalance <= 1 + balance_.imbalance) return;
        rank_bytes local(count.size() * sizeof(std::uint64_t));
        std::memcpy(local.data(), count.data(), local.size());
        std::fill(count.begin(), count.end(), 0);
        for (const rank_bytes& b : all_gather(local))
            for (std::size_t c = 0; c < count.size(); ++c) count[c] += value_of<std::uint64_t>(b, c * sizeof(std::uint64_t));
        cut_choice choice = choose_cut(g, count);
        if (choice.axis == axis_ && choice.bounds == bounds_) return;
        if (before_rebalance_) before_rebalance_();
        set_cut(g, std::move(choice));
        ++rebalances_;
    }

    std::vector<rank_bytes> exchange(const std::vector<rank_bytes>& out) {
        for (const rank_bytes& b : out) bytes_sent_ += b.size();
        span_timer timed{step_wait_};
        return comm_->exchange(out);
    }
    std::vector<rank_bytes> all_gather(const rank_bytes& mine) {
        span_timer timed{step_wait_};
        return comm_->all_gather(mine);
    }

    /// A step starts with redistribute(): the last one's times are added up (its time without
    /// gather()'s output, and its exchanges), and a new one is timed.
    void start_step() {
        const clock::time_point now = clock::now();
        if (step_start_ != clock::time_point{}) {
            step_seconds_ += std::chrono::duration<double>(now - step_start_).count() - step_output_;
            exchange_seconds_ += step_exchange_;
            wait_seconds_ += step_wait_;
            ++timed_steps_;
        }
        step_start_ = now;
        step_output_ = step_exchange_ = step_wait_ = 0;
    }

    cell_index cell(const grid_geometry<float>& g, std::size_t i) const {
        const std::vector<float>& x = *fields_[0].data;
        std::array<float, D> p;
        for (int a = 0; a < D; ++a) p[std::size_t(a)] = x[i * D + std::size_t(a)] * g.scale;
        return g.cell_of(p);
    }
    std::int64_t plane(const grid_geometry<float>& g, std::size_t i) const { return cell(g, i)[std::size_t(axis_)]; }
    int owner(std::int64_t c) const {
        const auto it = std::upper_bound(bounds_.begin(), bounds_.end(), c);
        return int(std::clamp<std::ptrdiff_t>(it - bounds_.begin() - 1, 0, comm_->size() - 1));
    }
    /// Whether rank q's slab holds a plane within `reach` of plane c (around the box on a
    /// periodic axis).
    bool near(int q, std::int64_t c, int reach) const {
        const std::int64_t lo = bounds_[std::size_t(q)], hi = bounds_[std::size_t(q) + 1];
        if (lo >= hi) return false;
        if (!wraps_) return c + reach >= lo && c - reach < hi;
        for (std::int64_t d = -reach; d <= reach; ++d) {
            const std::int64_t p = ((c + d) % planes_ + planes_) % planes_;
            if (p >= lo && p < hi) return true;
        }
        return false;
    }

    void pack(rank_bytes& b, std::size_t i, const std::vector<std::uint32_t>& id) const {
        append(b, key_[i]);
        append(b, id[i]);
        for (const auto& f : fields_)
            for (std::size_t c = 0; c < f.components; ++c) append(b, (*f.data)[i * f.components + c]);
    }
    void unpack(const rank_bytes& b, std::vector<std::uint32_t>& id, std::uint8_t ghost) {
        std::size_t floats = 0;
        for (const auto& f : fields_) floats += f.components;
        const std::size_t record = sizeof(order_key) + sizeof(std::uint32_t) + floats * sizeof(float);
        if (b.size() % record) throw error("ranks: a particle message of " + std::to_string(b.size()) + " bytes");
        for (std::size_t at = 0; at < b.size();) {
            key_.push_back(value_of<order_key>(b, at)), at += sizeof(order_key);
            id.push_back(value_of<std::uint32_t>(b, at)), at += sizeof(std::uint32_t);
            ghost_.push_back(ghost);
            for (const auto& f : fields_)
                for (std::size_t c = 0; c < f.components; ++c) f.data->push_back(value_of<float>(b, at)), at += sizeof(float);
        }
    }
    /// new[k] = old[order[k]] for every carried array and the flags. Each array is written into
    /// a spare of last step's size and swapped with it: no fresh memory (and page faults) per step.
    void permute(const std::vector<std::uint32_t>& order, std::vector<std::uint32_t>& id) {
        auto take = [&](auto& v, auto& spare, std::size_t components) {
            spare.resize(order.size() * components);
            for (std::size_t k = 0; k < order.size(); ++k)
                for (std::size_t c = 0; c < components; ++c) spare[k * components + c] = v[std::size_t(order[k]) * components + c];
            v.swap(spare);
        };
        spare_fields_.resize(fields_.size());
        for (std::size_t f = 0; f < fields_.size(); ++f) take(*fields_[f].data, spare_fields_[f], fields_[f].components);
        take(id, spare_id_, 1);
        take(key_, spare_key_, 1);
        take(ghost_, spare_ghost_, 1);
    }

    std::shared_ptr<rank_comm> comm_;
    balance_options balance_;
    std::function<void()> before_rebalance_;
    std::uint64_t steps_ = 0, bytes_sent_ = 0;
    // Per step: its start, and its seconds in gather()'s output, in this class's exchanges and
    // waiting inside them (part of the exchanges); the totals over the steps that ended.
    clock::time_point step_start_{};
    double step_output_ = 0, step_exchange_ = 0, step_wait_ = 0;
    double step_seconds_ = 0, exchange_seconds_ = 0, wait_seconds_ = 0;
    std::uint64_t timed_steps_ = 0;
    std::size_t checks_ = 0, rebalances_ = 0;
    double largest_imbalance_ = 0, imbalance_sum_ = 0;
    std::vector<carried_field> fields_;
    int axis_ = 0, depth_ = 1;
    bool wraps_ = false;  ///< the cut axis is periodic
    std::int64_t planes_ = 1;
    std::vector<std::int64_t> bounds_;  ///< rank q owns planes [bounds_[q], bounds_[q + 1])
    std::vector<std::uint8_t> ghost_;
    std::vector<order_key> key_;
    std::vector<std::uint32_t> tag_;
    std::size_t owned_ = 0;
    std::vector<std::vector<std::uint32_t>> sent_, got_;  ///< ghost exchange lists, per rank
    std::size_t slots_before_ = 0;  ///< the arrays' length before the last permute()
    std::vector<std::pair<std::uint32_t, int>> departures_;  ///< (id, rank) of the last redistribute()
    std::vector<std::vector<float>> spare_fields_;  ///< permute()'s spare arrays
    std::vector<std::uint32_t> spare_id_;
    std::vector<order_key> spare_key_;
    std::vector<std::uint8_t> spare_ghost_;
};

}  // namespace frnn::sim::detail
