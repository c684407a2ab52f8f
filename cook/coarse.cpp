// Cooking the coarse level (hierarchical correction; Mueller, Hierarchical Position Based Dynamics,
// VRIPHYS 2008). Works on any triangle mesh: every distance below is measured along the mesh's
// edges (a bounded Dijkstra on rest lengths), so panels that overlap in 2-D rest coordinates never
// see each other.
//
//   1. nodes: particles at least `spacing` apart along the mesh, pinned particles considered first
//      (they become pinned nodes that anchor the coarse cloth);
//   2. weights: each particle takes its kCoarseWeights nearest nodes within 1.25 spacing, weight
//      (1 - d / R)^2, normalised to a partition of unity (0 on pinned particles);
//   3. constraints: between the two nearest nodes of every particle, rest length the straight rest
//      distance where the mesh between them is flat enough (graph distance <= 1.5 x straight),
//      otherwise the graph distance;
//   4. node masses: the weighted sum of the particles' masses;
//   5. the constraints as lanes and batches over node slots, cooked like the fine springs.
#include "cook/coarse.h"
#include "cook/lanes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace weft {
namespace {

struct Adjacency {
    std::vector<uint32_t> start;  // CSR over caller particles
    std::vector<uint32_t> neighbour;
    std::vector<float> length;
};

float rest_distance(const Vec3& p, const Vec3& q) {
    const double dx = double(p.x) - q.x, dy = double(p.y) - q.y, dz = double(p.z) - q.z;
    return float(std::sqrt(dx * dx + dy * dy + dz * dz));
}

Adjacency build_adjacency(const ClothMeshDesc& mesh, const Vec3* rest) {
    std::vector<std::pair<uint32_t, uint32_t>> edges;
    edges.reserve(size_t(mesh.triangle_count) * 6);
    for (uint32_t t = 0; t < mesh.triangle_count; ++t) {
        const uint32_t* v = mesh.triangles + 3 * t;
        for (int e = 0; e < 3; ++e) {
            edges.push_back({v[e], v[(e + 1) % 3]});
            edges.push_back({v[(e + 1) % 3], v[e]});
        }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    Adjacency adj;
    adj.start.assign(mesh.particle_count + 1, 0);
    for (const auto& e : edges) adj.start[e.first + 1] += 1;
    for (uint32_t i = 0; i < mesh.particle_count; ++i) adj.start[i + 1] += adj.start[i];
    adj.neighbour.resize(edges.size());
    adj.length.resize(edges.size());
    for (size_t k = 0; k < edges.size(); ++k) {  // edges are sorted by source: CSR order already
        adj.neighbour[k] = edges[k].second;
        adj.length[k] = rest_distance(rest[edges[k].first], rest[edges[k].second]);
    }
    return adj;
}

// Bounded Dijkstra from `source`; calls visit(particle, distance) for every particle within radius.
// `dist` must be all +inf on entry and is restored to +inf on exit (so one buffer serves every call).
template <class Visit>
void bounded_dijkstra(const Adjacency& adj, uint32_t source, float radius, std::vector<float>& dist,
                      std::vector<uint32_t>& touched, Visit visit) {
    using Item = std::pair<float, uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    touched.clear();
    dist[source] = 0.0f;
    touched.push_back(source);
    queue.push({0.0f, source});
    while (!queue.empty()) {
        const auto [d, p] = queue.top();
        queue.pop();
        if (d > dist[p]) continue;
        visit(p, d);
        for (uint32_t k = adj.start[p]; k < adj.start[p + 1]; ++k) {
            const uint32_t q = adj.neighbour[k];
            const float nd = d + adj.length[k];
            if (nd <= radius && nd < dist[q]) {
                if (dist[q] == std::numeric_limits<float>::infinity()) touched.push_back(q);
                dist[q] = nd;
                queue.push({nd, q});
            }
        }
    }
    for (uint32_t p : touched) dist[p] = std::numeric_limits<float>::infinity();
}

// Node masses: each particle's mass spread over its nodes by weight. Fills coarse_node_slot and
// returns the nodes' inverse masses (0 for pinned nodes).
std::vector<float> assign_node_masses(const std::vector<uint32_t>& nodes, const std::vector<float>& mass,
                                      const std::vector<float>& inverse_mass, uint32_t n, CookedCloth& out) {
    std::vector<double> node_mass(nodes.size(), 0.0);
    for (uint32_t p = 0; p < n; ++p) {
        const uint32_t slot = out.slot_of_particle[p];
        for (uint32_t k = 0; k < kCoarseWeights; ++k)
            node_mass[out.coarse_weight_node[k][slot]] += double(out.coarse_weight[k][slot]) * mass[p];
    }
    std::vector<float> node_inverse_mass(nodes.size());
    for (uint32_t j = 0; j < nodes.size(); ++j) {
        out.coarse_node_slot.push_back(out.slot_of_particle[nodes[j]]);
        const bool pinned = inverse_mass[nodes[j]] == 0.0f || !(node_mass[j] > 0.0);
        node_inverse_mass[j] = pinned ? 0.0f : float(1.0 / node_mass[j]);
    }
    return node_inverse_mass;
}

// The coarse constraints (node pairs a < b with rest lengths, in `constraints`) as lanes and batches
// over node slots, cooked exactly like the fine springs (cook_lanes): runs where the node slots make
// them, first-fit colours, so the step solves them with the fine springs' kernels.
void emit_coarse_constraints(const std::vector<Spring>& constraints, const std::vector<uint32_t>& slot_of_node,
                             uint32_t slot_count, const std::vector<float>& node_inverse_mass,
                             const CookOptions& options, CookedCloth& out) {
    std::vector<Spring> springs;
    for (const Spring& c : constraints) {
        if (node_inverse_mass[c.a] == 0.0f && node_inverse_mass[c.b] == 0.0f) continue;  // moves nothing
        const uint32_t sa = slot_of_node[c.a], sb = slot_of_node[c.b];
        springs.push_back({std::min(sa, sb), std::max(sa, sb), ConstraintKind::stretch, c.rest});
    }
    out.coarse_constraint_count = uint32_t(springs.size());
    uint32_t on_runs = 0;
    out.coarse_colour_count = cook_lanes(std::move(springs), slot_count, options,
                                         {out.coarse_rest_length, out.coarse_lane_weight, out.coarse_index_a,
                                          out.coarse_index_b, out.coarse_batches},
                                         &on_runs);
    const uint32_t width = options.simd_width;
    slot_count = (slots_touched(out.coarse_batches, slot_count) + width - 1) / width * width;
    out.coarse_slot_of_node = slot_of_node;
    out.coarse_node_of_slot.assign(slot_count, 0);
    out.coarse_inverse_mass.assign(slot_count, 0.0f);
    for (uint32_t j = 0; j < slot_of_node.size(); ++j) {
        out.coarse_node_of_slot[slot_of_node[j]] = j;
        out.coarse_inverse_mass[slot_of_node[j]] = node_inverse_mass[j];
    }
}

// Node coordinates along one lattice axis of `count` points: every `step`, and the last point.
std::vector<uint32_t> axis_nodes(uint32_t count, uint32_t step) {
    std::vector<uint32_t> u;
    for (uint32_t v = 0; v + 1 < count; v += step) u.push_back(v);
    if (u.size() > 1 && (count - 1) - u.back() < step / 2) u.back() = count - 1;  // no sliver cell
    else u.push_back(count - 1);
    return u;
}

struct AxisCell {
    uint32_t cell;  // node u[cell] <= v <= u[cell + 1]
    float frac;     // weight of node cell + 1
};
AxisCell locate(const std::vector<uint32_t>& u, uint32_t v) {
    uint32_t c = 0;
    while (c + 2 < u.size() && u[c + 1] <= v) ++c;
    return {c, float(v - u[c]) / float(u[c + 1] - u[c])};
}

// The lattice form: nodes every `step` lattice points, bilinear weights (see ClothAsset).
void build_lattice_level(const LatticeLayout& layout, const Vec3* rest, const std::vector<float>& mass,
                         const std::vector<float>& inverse_mass, uint32_t n, float spacing_m,
                         const CookOptions& options, CookedCloth& out) {
    auto particle = [&](uint32_t i, uint32_t j) { return out.particle_of_slot[layout.slot(i, j)]; };
    // Fine spacing: the mean rest length of the lattice's axis edges.
    double sum = 0.0;
    uint64_t edges = 0;
    for (uint32_t i = 0; i < layout.fine_rows; ++i)
        for (uint32_t j = 0; j < layout.fine_cols; ++j) {
            if (j + 1 < layout.fine_cols) sum += rest_distance(rest[particle(i, j)], rest[particle(i, j + 1)]), ++edges;
            if (i + 1 < layout.fine_rows) sum += rest_distance(rest[particle(i, j)], rest[particle(i + 1, j)]), ++edges;
        }
    const double edge = edges > 0 ? sum / double(edges) : 0.0;
    uint32_t step = edge > 0.0 ? uint32_t(std::lround(spacing_m / edge / 2.0)) * 2 : 2;
    // At most 32 nodes along an axis (validate_asset's bound on a coarse row).
    const uint32_t longest = std::max(layout.fine_rows, layout.fine_cols);
    step = std::max({step, 2u, 2 * ((longest - 1 + 61) / 62)});
    const std::vector<uint32_t> ui = axis_nodes(layout.fine_rows, step), uj = axis_nodes(layout.fine_cols, step);
    const uint32_t rows = uint32_t(ui.size()), cols = uint32_t(uj.size());
    std::vector<uint32_t> nodes;
    for (uint32_t I = 0; I < rows; ++I)
        for (uint32_t J = 0; J < cols; ++J) nodes.push_back(particle(ui[I], uj[J]));

    // Bilinear weights (the general form's arrays hold them too).
    for (uint32_t i = 0; i < layout.fine_rows; ++i) {
        const AxisCell ci = locate(ui, i);
        for (uint32_t j = 0; j < layout.fine_cols; ++j) {
            const uint32_t p = particle(i, j), slot = out.slot_of_particle[p];
            if (inverse_mass[p] == 0.0f) continue;
            const AxisCell cj = locate(uj, j);
            const uint32_t node[4] = {ci.cell * cols + cj.cell, (ci.cell + 1) * cols + cj.cell,
                                      ci.cell * cols + cj.cell + 1, (ci.cell + 1) * cols + cj.cell + 1};
            const float w[4] = {(1.0f - ci.frac) * (1.0f - cj.frac), ci.frac * (1.0f - cj.frac),
                                (1.0f - ci.frac) * cj.frac, ci.frac * cj.frac};
            for (uint32_t k = 0; k < kCoarseWeights; ++k) {
                out.coarse_weight_node[k][slot] = node[k];
                out.coarse_weight[k][slot] = w[k];
            }
        }
    }
    // Per plane row and column: the coarse row / column and the fraction (holes get 0, 0).
    out.coarse_lattice_cols = cols;
    out.lattice_plane_rows = layout.plane_rows;
    out.lattice_plane_cols = layout.plane_cols;
    for (uint32_t parity = 0; parity < 2; ++parity) {
        out.coarse_row_node[parity].assign(layout.plane_rows, 0);
        out.coarse_row_frac[parity].assign(layout.plane_rows, 0.0f);
        out.coarse_col_node[parity].assign(layout.plane_cols, 0);
        out.coarse_col_frac[parity].assign(layout.plane_cols, 0.0f);
        for (uint32_t r = 0; r < layout.plane_rows; ++r) {
            // A hole row past the lattice keeps the last coarse row (the kernel walks rows upwards).
            const AxisCell c = locate(ui, std::min(2 * r + parity, layout.fine_rows - 1));
            out.coarse_row_node[parity][r] = c.cell;
            out.coarse_row_frac[parity][r] = c.frac;
        }
        for (uint32_t c = 0; c < layout.plane_cols; ++c) {
            const AxisCell a = locate(uj, std::min(2 * c + parity, layout.fine_cols - 1));
            out.coarse_col_node[parity][c] = a.cell;
            out.coarse_col_frac[parity][c] = a.frac;
        }
    }
    // Constraints: the cells' edges and both diagonals (as the measured prototype).
    std::vector<Spring> constraints;
    auto join = [&](uint32_t a, uint32_t b) {
        constraints.push_back({a, b, ConstraintKind::stretch, rest_distance(rest[nodes[a]], rest[nodes[b]])});
    };
    for (uint32_t I = 0; I < rows; ++I)
        for (uint32_t J = 0; J < cols; ++J) {
            const uint32_t a = I * cols + J;
            if (J + 1 < cols) join(a, a + 1);
            if (I + 1 < rows) join(a, a + cols);
            if (I + 1 < rows && J + 1 < cols) join(a, a + cols + 1), join(a + 1, a + cols);
        }
    // Node slots: node (I, J) in parity plane (I & 1, J & 1), as the fine particles, so every family
    // joins two planes at one constant offset and becomes runs. The planes are spaced a little
    // wider than they are long (one plane row more), so that no family's run reaches its own b side.
    const uint32_t plane_rows = (rows + 1) / 2, plane_cols = (cols + 1) / 2;
    const uint32_t plane_stride = (plane_rows * plane_cols + plane_cols + kSimdWidth - 1) / kSimdWidth * kSimdWidth;
    std::vector<uint32_t> slot_of_node(nodes.size());
    for (uint32_t I = 0; I < rows; ++I)
        for (uint32_t J = 0; J < cols; ++J)
            slot_of_node[I * cols + J] = ((I & 1) * 2 + (J & 1)) * plane_stride + (I >> 1) * plane_cols + (J >> 1);
    const std::vector<float> node_inverse_mass = assign_node_masses(nodes, mass, inverse_mass, n, out);
    emit_coarse_constraints(constraints, slot_of_node, 4 * plane_stride, node_inverse_mass, options, out);
}

}  // namespace

void build_coarse_level(const ClothMeshDesc& mesh, const LatticeLayout& layout, const std::vector<float>& mass,
                        const std::vector<float>& inverse_mass, const CookOptions& options, CookedCloth& out) {
    const float spacing_m = options.coarse_spacing_m;
    const uint32_t n = mesh.particle_count;
    const uint32_t slots = uint32_t(out.particle_of_slot.size());
    for (uint32_t k = 0; k < kCoarseWeights; ++k) {
        out.coarse_weight_node[k].assign(slots, 0);
        out.coarse_weight[k].assign(slots, 0.0f);
    }
    if (!(spacing_m > 0.0f) || mesh.triangle_count == 0) return;
    const Vec3* rest = mesh.rest_positions ? mesh.rest_positions : mesh.positions;
    if (layout.full && layout.fine_rows >= 2 && layout.fine_cols >= 2) {
        build_lattice_level(layout, rest, mass, inverse_mass, n, spacing_m, options, out);
        return;
    }
    const Adjacency adj = build_adjacency(mesh, rest);
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<float> dist(n, inf);
    std::vector<uint32_t> touched;

    // 1. Nodes: greedy, pinned particles first, then in caller order.
    std::vector<float> nearest_node(n, inf);
    std::vector<uint32_t> nodes;
    auto consider = [&](uint32_t p) {
        if (nearest_node[p] < spacing_m) return;
        nodes.push_back(p);
        bounded_dijkstra(adj, p, spacing_m, dist, touched,
                         [&](uint32_t q, float d) { nearest_node[q] = std::min(nearest_node[q], d); });
    };
    for (uint32_t p = 0; p < n; ++p)
        if (inverse_mass[p] == 0.0f) consider(p);
    for (uint32_t p = 0; p < n; ++p)
        if (inverse_mass[p] != 0.0f) consider(p);
    if (nodes.size() < 2) return;

    // 2. Weights: the kCoarseWeights nearest nodes within R of every particle.
    const float radius = 1.25f * spacing_m;
    struct Candidate {
        float distance;
        uint32_t node;
    };
    std::vector<std::array<Candidate, kCoarseWeights>> best(n);
    for (auto& b : best) b.fill({inf, 0});
    for (uint32_t j = 0; j < nodes.size(); ++j) {
        bounded_dijkstra(adj, nodes[j], radius, dist, touched, [&](uint32_t q, float d) {
            auto& b = best[q];
            if (d >= b[kCoarseWeights - 1].distance) return;
            uint32_t k = kCoarseWeights - 1;
            for (; k > 0 && b[k - 1].distance > d; --k) b[k] = b[k - 1];
            b[k] = {d, j};
        });
    }
    for (uint32_t p = 0; p < n; ++p) {
        if (inverse_mass[p] == 0.0f) continue;  // pinned particles never move
        float w[kCoarseWeights] = {}, sum = 0.0f;
        for (uint32_t k = 0; k < kCoarseWeights; ++k) {
            if (best[p][k].distance == inf) continue;
            const float u = 1.0f - best[p][k].distance / radius;
            w[k] = u * u;
            sum += w[k];
        }
        if (!(sum > 0.0f)) continue;
        const uint32_t slot = out.slot_of_particle[p];
        for (uint32_t k = 0; k < kCoarseWeights; ++k) {
            out.coarse_weight_node[k][slot] = best[p][k].distance == inf ? 0 : best[p][k].node;
            out.coarse_weight[k][slot] = w[k] / sum;
        }
    }

    // 3. Constraints between nodes whose regions touch: the two nearest nodes of some particle
    //    (a Delaunay-like neighbourhood: edges and diagonals of the node pattern).
    std::vector<std::pair<uint32_t, uint32_t>> pairs;
    for (uint32_t p = 0; p < n; ++p) {
        if (best[p][1].distance == inf) continue;
        const uint32_t a = best[p][0].node, b = best[p][1].node;
        pairs.push_back({std::min(a, b), std::max(a, b)});
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    std::vector<Spring> constraints;
    for (const auto& [a, b] : pairs) {
        if (inverse_mass[nodes[a]] == 0.0f && inverse_mass[nodes[b]] == 0.0f) continue;
        float graph = inf;
        const uint32_t target = nodes[b];  // named: clang 14 cannot capture a structured binding
        bounded_dijkstra(adj, nodes[a], 3.0f * radius, dist, touched, [&](uint32_t q, float d) {
            if (q == target) graph = std::min(graph, d);
        });
        const float straight = rest_distance(rest[nodes[a]], rest[nodes[b]]);
        constraints.push_back({a, b, ConstraintKind::stretch, (graph != inf && graph > 1.5f * straight) ? graph : straight});
    }

    // 4. and 5. Node masses; node j in node slot j (no lattice to make runs from: the constraints go
    //    mostly to coloured indexed batches).
    const std::vector<float> node_inverse_mass = assign_node_masses(nodes, mass, inverse_mass, n, out);
    std::vector<uint32_t> slot_of_node(nodes.size());
    for (uint32_t j = 0; j < nodes.size(); ++j) slot_of_node[j] = j;
    emit_coarse_constraints(constraints, slot_of_node, uint32_t(nodes.size()), node_inverse_mass, options, out);
}

}  // namespace weft
