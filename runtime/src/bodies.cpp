// Body colliders at the API: adding a body (its Embree scene over the offset hull), moving it,
// queries for tests and tools, and releasing Embree with the world. The pass is collide/body.cpp.
#include <cmath>
#include <cstring>

#include "world_internal.h"

namespace weft {

Result find_body(const World* world, BodyId id) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    if (Result r = refuse_while_stepping(world); !r.ok()) return r;
    return check_id(world->bodies, world->desc.max_bodies, id.index, id.generation, "body");
}

namespace {

constexpr float kMaxCoordinate_m = 1e5f;  // beyond this a millimetre contact no longer resolves in float

// Every position finite and within kMaxCoordinate_m: checked before anything is written.
Result check_positions(const Vec3* positions, uint32_t count) {
    for (uint32_t i = 0; i < count; ++i) {
        const Vec3 v = positions[i];
        if (!is_finite(v)) return make_error(ErrorCode::non_finite, "body vertex %u is not finite", i);
        if (std::fabs(v.x) > kMaxCoordinate_m || std::fabs(v.y) > kMaxCoordinate_m || std::fabs(v.z) > kMaxCoordinate_m)
            return make_error(ErrorCode::out_of_range, "body vertex %u beyond %g m", i, double(kMaxCoordinate_m));
    }
    return {};
}

Result check_body_desc(const World& world, const BodyDesc& desc) {
    if (world.desc.max_bodies == 0)
        return make_error(ErrorCode::invalid_argument, "world was created without bodies (max_bodies 0)");
    if (desc.positions == nullptr || desc.triangles == nullptr)
        return make_error(ErrorCode::invalid_argument, "body positions or triangles are null");
    if (desc.vertex_count < 3 || desc.triangle_count < 1)
        return make_error(ErrorCode::invalid_argument, "a body needs at least 3 vertices and 1 triangle");
    if (!std::isfinite(desc.thickness_m) || !std::isfinite(desc.margin_m) || !std::isfinite(desc.friction))
        return make_error(ErrorCode::non_finite, "body thickness, margin or friction is not finite");
    if (desc.thickness_m < 0.0f || desc.margin_m < 0.0f || desc.friction < 0.0f)
        return make_error(ErrorCode::out_of_range, "body thickness, margin and friction must be >= 0");
    if (!(desc.thickness_m + desc.margin_m > 0.0f) || desc.thickness_m + desc.margin_m > 1.0f)
        return make_error(ErrorCode::out_of_range, "body thickness + margin %g m outside (0, 1]",
                          double(desc.thickness_m + desc.margin_m));
    if (desc.collision != BodyCollision::exact && desc.collision != BodyCollision::cached_planes &&
        desc.collision != BodyCollision::skin_constraints)
        return make_error(ErrorCode::invalid_argument, "unknown body collision model %u", unsigned(desc.collision));
    if (free_slot(world.bodies, world.body_slots, world.desc.max_bodies) == world.desc.max_bodies)
        return make_error(ErrorCode::capacity_exceeded, "world holds at most %u bodies", world.desc.max_bodies);
    if (desc.collision == BodyCollision::cached_planes && world.cached_plane_bodies >= world.desc.max_cached_plane_bodies)
        return make_error(ErrorCode::capacity_exceeded,
                          "cached_planes: the world has contact planes for %u bodies "
                          "(WorldDesc::max_cached_plane_bodies), all taken",
                          world.desc.max_cached_plane_bodies);
    if (desc.vertex_count > world.desc.max_body_vertices - world.body_vertices_used)
        return make_error(ErrorCode::capacity_exceeded, "body needs %u vertices, %u left", desc.vertex_count,
                          world.desc.max_body_vertices - world.body_vertices_used);
    if (desc.triangle_count > world.desc.max_body_triangles - world.body_triangles_used)
        return make_error(ErrorCode::capacity_exceeded, "body needs %u triangles, %u left", desc.triangle_count,
                          world.desc.max_body_triangles - world.body_triangles_used);
    for (uint32_t i = 0; i < 3 * desc.triangle_count; ++i)
        if (desc.triangles[i] >= desc.vertex_count)
            return make_error(ErrorCode::out_of_range, "triangle %u uses vertex %u of %u", i / 3, desc.triangles[i],
                              desc.vertex_count);
    return check_positions(desc.positions, desc.vertex_count);
}

}  // namespace

void commit_body(World& world, BodyState& body) {
    if (world.commit_hook != nullptr) world.commit_hook(world.commit_hook_user, true);
    rtcCommitScene(body.scene);
    if (world.commit_hook != nullptr) world.commit_hook(world.commit_hook_user, false);
}

void refit_embree(World& world, BodyState& body) {
    rtcUpdateGeometryBuffer(body.geometry, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(body.geometry);
    commit_body(world, body);
    body.embree_refits += 1;
}

namespace {

// Embree reads the hull and the triangles in the world's block (no copy).
void share_buffers_with_embree(BodyState& body) {
    rtcSetSharedGeometryBuffer(body.geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, body.hull, 0,
                               4 * sizeof(float), body.vertex_count);
    rtcSetSharedGeometryBuffer(body.geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, body.triangles, 0,
                               3 * sizeof(uint32_t), body.triangle_count);
    rtcCommitGeometry(body.geometry);
}

// The Embree scene over the body's offset hull (shared buffers: Embree reads the hull and
// triangles in the world's block, no copy). Refit, not rebuild, when the body moves: only this
// combination refits in Embree 3.13.5 (any other rebuilds from scratch on every commit).
Result build_embree_scene(World& world, BodyState& body) {
    RTCDevice device = world.embree_device;
    body.scene = rtcNewScene(device);
    rtcSetSceneFlags(body.scene, RTC_SCENE_FLAG_DYNAMIC);
    rtcSetSceneBuildQuality(body.scene, RTC_BUILD_QUALITY_LOW);
    body.geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(body.geometry, RTC_BUILD_QUALITY_REFIT);
    share_buffers_with_embree(body);
    rtcAttachGeometry(body.scene, body.geometry);
    commit_body(world, body);
    if (const RTCError error = rtcGetDeviceError(device); error != RTC_ERROR_NONE) {
        rtcReleaseGeometry(body.geometry);
        rtcReleaseScene(body.scene);
        return make_error(ErrorCode::unsupported, "Embree failed to build the body's BVH (error %d)", int(error));
    }
    return {};
}

// A body's arrays: the hull and previous hull (4 floats a vertex), normals (3), triangles (3 indices).
// The +4 pads let Embree read its buffers' last element with one 16-byte load (Embree docs,
// rtcSetSharedGeometryBuffer); skin_frames loads 16 bytes a normal.
struct BodyArrays {
    float* hull = nullptr;
    float* previous_hull = nullptr;
    float* normals = nullptr;
    uint32_t* triangles = nullptr;
};
template <class Room>
BodyArrays carve_body_arrays(Room& room, uint32_t v, uint32_t t) {
    BodyArrays a;
    a.hull = room.template allocate_array<float>(4 * size_t(v) + 4);
    a.previous_hull = room.template allocate_array<float>(4 * size_t(v));
    a.normals = room.template allocate_array<float>(3 * size_t(v) + 4);
    a.triangles = room.template allocate_array<uint32_t>(3 * size_t(t) + 4);
    return a;
}

// Counts what carve_body_arrays takes (ArenaSizer's rounding), for body_region_bytes.
struct RoomSizer {
    ArenaSizer sizer;
    template <class T>
    T* allocate_array(size_t count) {
        sizer.add(sizeof(T) * count);
        return nullptr;
    }
};

}  // namespace

size_t body_region_bytes(uint32_t vertex_count, uint32_t triangle_count) {
    RoomSizer room;
    carve_body_arrays(room, vertex_count, triangle_count);
    return align_up(room.sizer.bytes, kCacheLine) + body_hierarchy_bytes(triangle_count, 1);
}

namespace {

Result add_body_searched_by(World* world, const BodyDesc& desc, bool reference_queries, BodyId* out_body) {
    if (world == nullptr || out_body == nullptr)
        return make_error(ErrorCode::invalid_argument, "world or out_body is null");
    if (Result r = refuse_while_stepping(world); !r.ok()) return r;
    if (Result r = check_body_desc(*world, desc); !r.ok()) return r;

    // Carve the arrays in a region of their own (body_region_bytes: the sizing says they fit).
    const uint32_t v = desc.vertex_count, t = desc.triangle_count;
    Arena room;
    Region region;
    if (Result r = reserve_instance_memory(*world, body_region_bytes(v, t), &room, &region); !r.ok()) return r;
    BodyArrays arrays = carve_body_arrays(room, v, t);
    std::memset(arrays.normals + 3 * size_t(v), 0, 4 * sizeof(float));
    const uint32_t index = free_slot(world->bodies, world->body_slots, world->desc.max_bodies);
    BodyState& body = world->bodies[index];
    const uint32_t generation = body.slot.generation;
    body = BodyState();
    body.slot = {true, generation, region};
    body.desc = desc;
    body.reference_queries = reference_queries;
    body.desc.positions = nullptr;  // the caller's arrays are not kept
    body.desc.triangles = nullptr;
    body.vertex_count = v;
    body.triangle_count = t;
    float* const hull = body.hull = arrays.hull;
    float* const previous = body.previous_hull = arrays.previous_hull;
    body.normals = arrays.normals;
    uint32_t* const triangles = body.triangles = arrays.triangles;
    std::memcpy(triangles, desc.triangles, sizeof(uint32_t) * 3 * size_t(t));
    std::memset(triangles + 3 * size_t(t), 0, sizeof(uint32_t) * 4);
    std::memset(hull + 4 * size_t(v), 0, sizeof(float) * 4);
    compute_offset_hull(body, desc.positions);
    std::memcpy(previous, hull, sizeof(float) * 4 * size_t(v));
    if (!build_body_hierarchy(body, room, world->kernels->path)) {  // cannot fail: body_region_bytes holds it
        body = BodyState();
        body.slot.generation = generation;
        return make_error(ErrorCode::capacity_exceeded, "world memory exhausted");
    }

    // Embree's BVH serves only the plain reference pass (add_reference_body); every other body is
    // searched through Weft's own hierarchy, so it neither builds nor holds one.
    if (reference_queries) {
        if (Result r = build_embree_scene(*world, body); !r.ok()) {
            body = BodyState();
            body.slot.generation = generation;
            return r;
        }
    }
    world->body_vertices_used += v;
    world->body_triangles_used += t;
    if (desc.collision == BodyCollision::cached_planes) {  // the lowest place no live body holds
        uint32_t place = 0;
        for (bool taken = true; taken; place += taken) {
            taken = false;
            for (uint32_t i = 0; i < world->body_slots; ++i)
                taken = taken || (i != index && world->bodies[i].slot.live && world->bodies[i].plane_index == place);
        }
        body.plane_index = place;
        world->cached_plane_bodies += 1;
    }
    world->body_slots = std::max(world->body_slots, index + 1);
    world->bodies_live += 1;
    wake_cloths_of_body(*world, index);  // the cloths that collide with every body meet it
    *out_body = {index, generation};
    return {};
}

}  // namespace

Result add_body(World* world, const BodyDesc& desc, BodyId* out_body) {
    return add_body_searched_by(world, desc, false, out_body);
}

Result add_reference_body(World* world, const BodyDesc& desc, BodyId* out_body) {
    return add_body_searched_by(world, desc, true, out_body);
}

Result remove_body(World* world, BodyId id) {
    if (Result r = find_body(world, id); !r.ok()) return r;
    for (uint32_t i = 0; i < world->cloth_slots; ++i) {
        const ClothInstance& c = world->cloths[i];
        if (c.slot.live && (c.own_body == id.index || c.skin_body == id.index || c.attached_body == id.index))
            return make_error(ErrorCode::invalid_argument,
                              "body %u still carries cloth %u (its own body, skin constraints or attachments): "
                              "remove the cloth first", id.index, i);
    }
    wake_cloths_of_body(*world, id.index);
    BodyState& body = world->bodies[id.index];
    if (body.scene != nullptr) {  // reference bodies only
        rtcReleaseGeometry(body.geometry);
        rtcReleaseScene(body.scene);
    }
    world->body_vertices_used -= body.vertex_count;
    world->body_triangles_used -= body.triangle_count;
    world->cached_plane_bodies -= body.desc.collision == BodyCollision::cached_planes;
    world->bodies_live -= 1;
    const InstanceSlot slot = body.slot;
    body = BodyState();
    body.slot = slot;
    release_slot(world->bodies, id.index, &world->body_slots);
    return {};
}

void rebase_body(World& world, BodyState& body, ptrdiff_t delta) {
    for (float** a : {&body.hull, &body.previous_hull, &body.normals}) rebase(*a, delta);
    rebase(body.triangles, delta);
    BodyHierarchy& h = body.hierarchy;
    rebase(h.leaf_triangle, delta);
    rebase(h.leaf_vertex, delta);
    rebase(h.leaf_corners, delta);
    rebase(h.leaf_sweep, delta);
    rebase(h.leaf_fold, delta);
    rebase(h.in_crease, delta);
    for (Boxes* boxes : {&h.leaves, &h.groups, &h.roots})
        for (float** a : {&boxes->min_x, &boxes->min_y, &boxes->min_z, &boxes->max_x, &boxes->max_y, &boxes->max_z})
            rebase(*a, delta);
    if (body.scene != nullptr) {  // Embree reads the hull and triangles where they now are
        share_buffers_with_embree(body);
        commit_body(world, body);
    }
}

namespace {

// A new pose for a body: the body exists, `count` is its vertex count, every position is sane.
Result check_pose(const World* world, BodyId id, const Vec3* positions, uint32_t count) {
    if (Result r = find_body(world, id); !r.ok()) return r;
    if (positions == nullptr) return make_error(ErrorCode::invalid_argument, "positions is null");
    if (count != world->bodies[id.index].vertex_count)
        return make_error(ErrorCode::out_of_range, "count %u, body has %u vertices", count,
                          world->bodies[id.index].vertex_count);
    return check_positions(positions, count);
}

}  // namespace

Result set_body_vertices(World* world, BodyId id, const Vec3* positions, uint32_t count) {
    if (Result r = check_pose(world, id, positions, count); !r.ok()) return r;
    BodyState& body = world->bodies[id.index];
    // The previous hull is the one the last step used: keep it across several calls before a step.
    if (!body.refit_pending) std::memcpy(body.previous_hull, body.hull, sizeof(float) * 4 * size_t(count));
    compute_offset_hull(body, positions, body.previous_hull);  // with each vertex's motion
    body.refit_pending = true;
    // A pose that differs from the last step's wakes the cloths it may move (the same pose does not).
    for (uint32_t v = 0; v < count; ++v) {
        const float* now = body.hull + 4 * size_t(v);
        const float* before = body.previous_hull + 4 * size_t(v);
        if (now[0] != before[0] || now[1] != before[1] || now[2] != before[2]) {
            wake_cloths_of_body(*world, id.index);
            break;
        }
    }
    return {};
}

Result teleport_body(World* world, BodyId id, const Vec3* positions, uint32_t count) {
    if (Result r = check_pose(world, id, positions, count); !r.ok()) return r;
    BodyState& body = world->bodies[id.index];
    compute_offset_hull(body, positions);
    hold_body_still(*world, id.index);
    body.refit_pending = true;
    wake_cloths_of_body(*world, id.index);
    return {};
}

void hold_body_still(World& world, uint32_t index) {
    BodyState& body = world.bodies[index];
    for (uint32_t v = 0; v < body.vertex_count; ++v) body.hull[4 * v + 3] = 0.0f;
    std::memcpy(body.previous_hull, body.hull, sizeof(float) * 4 * size_t(body.vertex_count));
    for (uint32_t i = 0; i < world.cloth_slots; ++i)
        if (world.cloths[i].slot.live && world.cloths[i].skin_body == index) world.cloths[i].skin_points_current = false;
}

Result set_cloth_body(World* world, ClothId cloth, BodyId body) {
    if (Result r = find_cloth(world, cloth); !r.ok()) return r;
    if (body.index != kEveryBody.index)
        if (Result r = find_body(world, body); !r.ok()) return r;
    wake(world->cloths[cloth.index]);
    world->cloths[cloth.index].own_body = body.index;
    return {};
}

Result query_body(const World* world, BodyId id, Vec3 point, BodyContact* out, float reach_m) {
    if (Result r = find_body(world, id); !r.ok()) return r;
    if (out == nullptr) return make_error(ErrorCode::invalid_argument, "out is null");
    if (!is_finite(point)) return make_error(ErrorCode::non_finite, "query point is not finite");
    if (!(reach_m >= 0.0f) || !(reach_m <= 100.0f))
        return make_error(ErrorCode::out_of_range, "query reach %g m outside [0, 100]", double(reach_m));
    const BodyState& body = world->bodies[id.index];
    if (body.refit_pending)
        return make_error(ErrorCode::invalid_argument, "body moved since the last step: step first");
    // A skin_constraints body's hierarchy is refitted on demand: the hierarchy is a cache of the
    // hull (no result of the world changes), so a query may bring it up to date. Queries on such
    // a body must therefore not run concurrently with each other.
    refresh_body_hierarchy(const_cast<BodyState&>(body), world->kernels->path);
    const float p[3] = {point.x, point.y, point.z};
    const float reach = reach_m > 0.0f ? reach_m : body.desc.thickness_m + body.desc.margin_m;
    *out = body.reference_queries ? closest_hull_point(body, p, reach)
                                       : closest_hull_point_hierarchy(body, p, reach, world->kernels->path);
    return {};
}

Result view_body(const World* world, BodyId id, BodyView* out) {
    if (Result r = find_body(world, id); !r.ok()) return r;
    if (out == nullptr) return make_error(ErrorCode::invalid_argument, "out is null");
    const BodyState& body = world->bodies[id.index];
    out->vertex_count = body.vertex_count;
    out->triangle_count = body.triangle_count;
    out->hull = body.hull;
    out->normals = body.normals;
    out->triangles = body.triangles;
    out->in_crease = body.hierarchy.in_crease;
    out->leaf_count = body.hierarchy.leaf_count;
    out->leaf_triangle = body.hierarchy.leaf_triangle;
    out->leaf_fold_m = body.hierarchy.leaf_fold;
    out->thickness_m = body.desc.thickness_m;
    out->margin_m = body.desc.margin_m;
    return {};
}

Result set_embree_commit_hook(World* world, EmbreeCommitHook hook, void* user) {
    if (world == nullptr) return make_error(ErrorCode::invalid_argument, "world is null");
    world->commit_hook = hook;
    world->commit_hook_user = user;
    return {};
}

void destroy_world(World* world) {
    if (world == nullptr) return;
    for (uint32_t i = 0; i < world->body_slots; ++i) {
        if (world->bodies[i].scene != nullptr) {  // reference bodies only
            rtcReleaseGeometry(world->bodies[i].geometry);
            rtcReleaseScene(world->bodies[i].scene);
        }
        world->bodies[i] = BodyState();
    }
    world->body_slots = 0;
    if (world->embree_device != nullptr) rtcReleaseDevice(world->embree_device);
    world->embree_device = nullptr;
}

}  // namespace weft
