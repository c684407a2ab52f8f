// The frame budget (weft/world.h: set_frame_budget_us; docs/architecture.md, "Frame budget").
//
// A game with many cloths gives the world a time in microseconds and each cloth a priority. Each
// step, before any work item runs, every awake cloth gets its own split (ClothDesc::sweeps through
// the budget policy, resolve_split); while the estimated cost of the step is over the budget, the
// lowest-priority cloth on the automatic policy is cut to the most sweeps that fit, down to
// kBudgetFloorSweeps, then the next lowest, and so on. The cut goes through the same resolve_split
// as the game's own sweeps, so a cut cloth runs exactly what it would with that ClothDesc::sweeps.
//
// The cost is a model, not a clock: WorldDesc::budget_ns_per_lane per constraint lane and sweep
// plus WorldDesc::budget_ns_per_particle per particle slot and substep, so the same inputs give the
// same splits (and bits) whatever the machine's load or thread count.
#include <algorithm>

#include "world_internal.h"

namespace weft {
namespace {

// The model's cost of one step of `split` on `asset`, in nanoseconds.
double step_cost_ns(const WorldDesc& desc, const ClothAsset& asset, const SolverSplit& split) {
    double lanes = double(split.iterations) * asset.total_constraints();  // one substep's sweeps
    if (split.coarse_level) lanes += double(split.coarse_iterations) * asset.coarse_constraint_count;
    return double(split.substeps) *
           (double(asset.slot_count) * desc.budget_ns_per_particle + lanes * desc.budget_ns_per_lane);
}

// The fewest sweeps the budget leaves a cloth: the floor, or its own sweeps when fewer.
uint32_t floor_sweeps(const ClothDesc& settings) { return std::min(settings.sweeps, kBudgetFloorSweeps); }

// The budget cuts only the automatic policy's one number; an explicit split is the game's exact choice.
bool may_cut(const ClothInstance& cloth) {
    return cloth.settings.policy == BudgetPolicy::automatic && cloth.settings.sweeps > floor_sweeps(cloth.settings);
}

}  // namespace

void spend_frame_budget(World& world) {
    const WorldDesc& desc = world.desc;
    const bool on = world.frame_budget_us > 0.0f;
    double estimate_ns = 0.0;
    uint32_t cuttable = 0;
    for (uint32_t i = 0; i < world.cloth_slots; ++i) {
        ClothInstance& c = world.cloths[i];
        if (!c.slot.live || c.sleeping) continue;  // a sleeping cloth's step runs nothing
        if (on) c.split = resolve_split(c.settings, *c.asset);  // its own split, before any cut
        estimate_ns += step_cost_ns(desc, *c.asset, c.split);
        if (on && may_cut(c)) world.budget_order[cuttable++] = i;
    }

    uint64_t cut = 0;
    const double budget_ns = 1000.0 * double(world.frame_budget_us);
    if (on && estimate_ns > budget_ns) {
        // Lowest priority first; of equal priorities, the highest slot first (a total order: the
        // same cut on every run).
        const ClothInstance* cloths = world.cloths;
        std::sort(world.budget_order, world.budget_order + cuttable, [cloths](uint32_t a, uint32_t b) {
            return cloths[a].priority != cloths[b].priority ? cloths[a].priority < cloths[b].priority : a > b;
        });
        for (uint32_t k = 0; k < cuttable && estimate_ns > budget_ns; ++k) {
            ClothInstance& c = world.cloths[world.budget_order[k]];
            const double own_ns = step_cost_ns(desc, *c.asset, c.split);
            ClothDesc trial = c.settings;  // the most sweeps that fit, else the floor
            for (trial.sweeps = c.settings.sweeps - 1; trial.sweeps > floor_sweeps(c.settings); --trial.sweeps)
                if (estimate_ns - own_ns + step_cost_ns(desc, *c.asset, resolve_split(trial, *c.asset)) <= budget_ns)
                    break;
            c.split = resolve_split(trial, *c.asset);
            estimate_ns += step_cost_ns(desc, *c.asset, c.split) - own_ns;
            cut += 1;
        }
    }

    WorldStats& stats = world.stats;
    stats.budget_estimate_us = estimate_ns / 1000.0;
    stats.budget_cloths_cut = cut;
    stats.budget_sweeps = 0;
    for (uint32_t i = 0; i < world.cloth_slots; ++i) {
        const ClothInstance& c = world.cloths[i];
        if (c.slot.live && !c.sleeping) stats.budget_sweeps += uint64_t(c.split.substeps) * c.split.iterations;
    }
}

}  // namespace weft
