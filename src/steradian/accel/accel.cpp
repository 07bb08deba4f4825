#include "steradian/accel/accel.h"

#include <embree3/rtcore.h>

#include <vector>

#include "steradian/core/error.h"

namespace sr {

namespace {

/// User-geometry payload for exact spheres and disks.
struct UserShape {
    const Sphere* sphere = nullptr;
    const Disk* disk = nullptr;
    const Cylinder* cylinder = nullptr;
    const AlphaMask* alpha = nullptr;
    unsigned geom_id = 0;
    unsigned mask = 0xFFFFFFFFu;  ///< the geometry's mask (tested here as well as by Embree)
};

/// Geometry masks: every geometry is hit by the rays of intersect() and occluded() (mask
/// ~0); an interface (a shape without a material: a luminous opening, a medium boundary)
/// lacks kScatteringBit, so the rays of occluded_by_surface() pass through it.
constexpr unsigned kScatteringBit = 1u, kInterfaceMask = 2u;

const Transform& object_transform(const UserShape& u) {
    return u.sphere ? u.sphere->world_from_object
           : u.disk ? u.disk->world_from_object
                    : u.cylinder->world_from_object;
}

void user_bounds(const RTCBoundsFunctionArguments* args) {
    const auto* us = static_cast<const UserShape*>(args->geometryUserPtr);
    Bounds3 ob;
    if (us->sphere) {
        Float r = us->sphere->radius;
        ob.expand(Point3(-r, -r, us->sphere->z_min));
        ob.expand(Point3(r, r, us->sphere->z_max));
    } else if (us->disk) {
        Float r = us->disk->radius;
        ob.expand(Point3(-r, -r, us->disk->height));
        ob.expand(Point3(r, r, us->disk->height));
    } else {
        Float r = us->cylinder->radius;
        ob.expand(Point3(-r, -r, us->cylinder->z_min));
        ob.expand(Point3(r, r, us->cylinder->z_max));
    }
    const Transform& t = object_transform(*us);
    Bounds3 wb;
    for (int i = 0; i < 8; ++i) {
        Point3 c((i & 1) ? ob.hi.x : ob.lo.x, (i & 2) ? ob.hi.y : ob.lo.y,
                 (i & 4) ? ob.hi.z : ob.lo.z);
        wb.expand(t.point(c));
    }
    // Pad for float rounding of the transformed corners.
    Vec3 pad = (wb.hi - wb.lo) * Float(1e-5) + Vec3(1e-6f, 1e-6f, 1e-6f);
    RTCBounds* b = args->bounds_o;
    b->lower_x = wb.lo.x - pad.x;
    b->lower_y = wb.lo.y - pad.y;
    b->lower_z = wb.lo.z - pad.z;
    b->upper_x = wb.hi.x + pad.x;
    b->upper_y = wb.hi.y + pad.y;
    b->upper_z = wb.hi.z + pad.z;
}

bool user_hit(const UserShape& us, Point3 o, Vec3 d, Float tnear, Float tfar, Float& t) {
    const Transform& x = object_transform(us);
    const Matrix4& inv = x.inverse_matrix();
    Transform obj_from(inv, x.matrix());
    Point3 oo = obj_from.point(o);
    Vec3 od = obj_from.vector(d);
    Point3 ph;
    Float th;
    if (us.cylinder || (us.sphere && us.alpha)) {
        // A cut-out lets the ray on to the far side.
        Float t_min = tnear;
        while (us.cylinder ? us.cylinder->intersect_object(oo, od, tfar, th, ph, t_min)
                           : us.sphere->intersect_object(oo, od, tfar, th, ph, t_min)) {
            SurfaceHit h;
            if (us.alpha) us.cylinder ? us.cylinder->fill_hit(ph, h) : us.sphere->fill_hit(ph, h);
            if (!us.alpha || alpha_stops(*us.alpha, h, o, d)) {
                t = th;
                return true;
            }
            t_min = th;
        }
        return false;
    }
    bool hit = us.sphere ? us.sphere->intersect_object(oo, od, tfar, th, ph)
                         : us.disk->intersect_object(oo, od, tfar, th, ph);
    if (!hit || th <= tnear) return false;
    if (us.alpha) {  // a disk's cut-out: a ray that passes meets nothing else of it
        SurfaceHit h;
        Point3 p_obj = oo + od * th;
        p_obj.z = us.disk->height;
        us.disk->fill_hit(p_obj, h);
        if (!alpha_stops(*us.alpha, h, o, d)) return false;
    }
    t = th;
    return true;
}

/// Embree's intersection and occlusion filter of a triangle mesh with alpha: rejects the
/// hits the rays pass through (Embree then goes on to the next hit).
void mesh_alpha_filter(const RTCFilterFunctionNArguments* args) {
    const auto* e = static_cast<const ShapeEntry*>(args->geometryUserPtr);
    const TriangleMesh& mesh = std::get<TriangleMesh>(e->geometry);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        SurfaceHit h;
        mesh.fill_hit(RTCHitN_primID(args->hit, args->N, i), RTCHitN_u(args->hit, args->N, i),
                      RTCHitN_v(args->hit, args->N, i), h);
        const Point3 o(RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                       RTCRayN_org_z(args->ray, args->N, i));
        const Vec3 d(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                     RTCRayN_dir_z(args->ray, args->N, i));
        if (!alpha_stops(*e->alpha, h, o, d)) args->valid[i] = 0;
    }
}

/// The alpha filter of a curve shape (as mesh_alpha_filter): the hit is filled from the
/// segment, Embree's curve parameter u and the hit distance (the ray's tfar in a filter).
void curve_alpha_filter(const RTCFilterFunctionNArguments* args) {
    const auto* e = static_cast<const ShapeEntry*>(args->geometryUserPtr);
    const Curves& curves = std::get<Curves>(e->geometry);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const Point3 o(RTCRayN_org_x(args->ray, args->N, i), RTCRayN_org_y(args->ray, args->N, i),
                       RTCRayN_org_z(args->ray, args->N, i));
        const Vec3 d(RTCRayN_dir_x(args->ray, args->N, i), RTCRayN_dir_y(args->ray, args->N, i),
                     RTCRayN_dir_z(args->ray, args->N, i));
        SurfaceHit h;
        curves.fill_hit(RTCHitN_primID(args->hit, args->N, i), RTCHitN_u(args->hit, args->N, i),
                        o, d, RTCRayN_tfar(args->ray, args->N, i), h);
        if (!alpha_stops(*e->alpha, h, o, d)) args->valid[i] = 0;
    }
}

void user_intersect(const RTCIntersectFunctionNArguments* args) {
    const auto* us = static_cast<const UserShape*>(args->geometryUserPtr);
    RTCRayHitN* rh = args->rayhit;
    RTCRayN* ray = RTCRayHitN_RayN(rh, args->N);
    RTCHitN* hit = RTCRayHitN_HitN(rh, args->N);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1 || !(RTCRayN_mask(ray, args->N, i) & us->mask)) continue;
        Point3 o(RTCRayN_org_x(ray, args->N, i), RTCRayN_org_y(ray, args->N, i),
                 RTCRayN_org_z(ray, args->N, i));
        Vec3 d(RTCRayN_dir_x(ray, args->N, i), RTCRayN_dir_y(ray, args->N, i),
               RTCRayN_dir_z(ray, args->N, i));
        Float t;
        if (!user_hit(*us, o, d, RTCRayN_tnear(ray, args->N, i), RTCRayN_tfar(ray, args->N, i), t))
            continue;
        RTCRayN_tfar(ray, args->N, i) = t;
        RTCHitN_Ng_x(hit, args->N, i) = 0;
        RTCHitN_Ng_y(hit, args->N, i) = 0;
        RTCHitN_Ng_z(hit, args->N, i) = 1;
        RTCHitN_u(hit, args->N, i) = 0;
        RTCHitN_v(hit, args->N, i) = 0;
        RTCHitN_primID(hit, args->N, i) = args->primID;
        RTCHitN_geomID(hit, args->N, i) = us->geom_id;
        RTCHitN_instID(hit, args->N, i, 0) = args->context->instID[0];
    }
}

void user_occluded(const RTCOccludedFunctionNArguments* args) {
    const auto* us = static_cast<const UserShape*>(args->geometryUserPtr);
    RTCRayN* ray = args->ray;
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1 || !(RTCRayN_mask(ray, args->N, i) & us->mask)) continue;
        Point3 o(RTCRayN_org_x(ray, args->N, i), RTCRayN_org_y(ray, args->N, i),
                 RTCRayN_org_z(ray, args->N, i));
        Vec3 d(RTCRayN_dir_x(ray, args->N, i), RTCRayN_dir_y(ray, args->N, i),
               RTCRayN_dir_z(ray, args->N, i));
        Float t;
        if (user_hit(*us, o, d, RTCRayN_tnear(ray, args->N, i), RTCRayN_tfar(ray, args->N, i), t))
            RTCRayN_tfar(ray, args->N, i) = -kInfinity;
    }
}

/// Embree's 8-ray packet of rays[i] for the bits i of `active`; the other lanes are marked
/// invalid (Embree does not trace them) and hold a copy of rays[0], so that every lane holds
/// finite values.
void put_packet(const Ray* rays, unsigned active, int* valid, RTCRay8& r8) {
    for (int i = 0; i < 8; ++i) {
        const bool on = (active >> i) & 1;
        valid[i] = on ? -1 : 0;
        const Ray& r = rays[on ? i : 0];
        r8.org_x[i] = r.o.x;
        r8.org_y[i] = r.o.y;
        r8.org_z[i] = r.o.z;
        r8.dir_x[i] = r.d.x;
        r8.dir_y[i] = r.d.y;
        r8.dir_z[i] = r.d.z;
        r8.tnear[i] = 0;
        r8.tfar[i] = r.t_max;
        r8.time[i] = 0;
        r8.mask[i] = 0xFFFFFFFF;
        r8.id[i] = 0;
        r8.flags[i] = 0;
    }
}

void error_callback(void*, RTCError code, const char* str) {
    if (code == RTC_ERROR_NONE) return;
    std::fprintf(stderr, "embree error %d: %s\n", int(code), str ? str : "");
}

}  // namespace

struct Accel::Impl {
    // Heap buffers of the scene's vectors: stable when the Scene object itself is moved.
    const ShapeEntry* shapes = nullptr;
    const Instance* instances = nullptr;
    RTCDevice device = nullptr;
    RTCScene top = nullptr;
    std::vector<RTCScene> proto_scenes;
    std::vector<int> top_geom_shape;                  ///< geomID -> shape (or -1: instance)
    std::vector<std::vector<int>> proto_geom_shape;   ///< per prototype: geomID -> shape
    std::vector<int> inst_geom_to_instance;           ///< top geomID -> instance
    std::vector<std::unique_ptr<UserShape>> user_shapes;
    bool masks = false;  ///< the Embree build tests ray masks (EMBREE_RAY_MASK)

    /// Attaches shape `shape_index` to scene `s`; a triangle mesh is built with `quality`
    /// (Embree builds each mesh of a RTC_BUILD_QUALITY_LOW scene on its own, with the
    /// mesh's quality: LOW is its Morton builder).
    unsigned attach_shape(RTCScene s, int shape_index, RTCBuildQuality quality) {
        const ShapeEntry& e = shapes[shape_index];
        RTCGeometry g = nullptr;
        UserShape* user = nullptr;
        if (const auto* mesh = std::get_if<TriangleMesh>(&e.geometry)) {
            g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
            if (quality == RTC_BUILD_QUALITY_LOW) rtcSetGeometryBuildQuality(g, quality);
            rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       mesh->p->data(), 0, sizeof(Point3), mesh->num_vertices());
            rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                       mesh->indices->data(), 0, 3 * sizeof(uint32_t),
                                       mesh->num_triangles());
            if (e.alpha) {
                rtcSetGeometryUserData(g, const_cast<ShapeEntry*>(&e));
                rtcSetGeometryIntersectFilterFunction(g, mesh_alpha_filter);
                rtcSetGeometryOccludedFilterFunction(g, mesh_alpha_filter);
            }
        } else if (const auto* curves = std::get_if<Curves>(&e.geometry)) {
            const bool ribbon = curves->type == CurveType::Ribbon;
            g = rtcNewGeometry(device, ribbon ? RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BEZIER_CURVE
                                              : RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE);
            rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                       curves->cp->data(), 0, sizeof(CurvePoint),
                                       curves->cp->size());
            rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT,
                                       curves->first->data(), 0, sizeof(uint32_t),
                                       curves->num_segments());
            if (ribbon)
                rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3,
                                           curves->embree_normals->data(), 0, sizeof(Normal3),
                                           curves->embree_normals->size() - 1);
            if (e.alpha) {
                rtcSetGeometryUserData(g, const_cast<ShapeEntry*>(&e));
                rtcSetGeometryIntersectFilterFunction(g, curve_alpha_filter);
                rtcSetGeometryOccludedFilterFunction(g, curve_alpha_filter);
            }
        } else {
            auto us = std::make_unique<UserShape>();
            us->sphere = std::get_if<Sphere>(&e.geometry);
            us->disk = std::get_if<Disk>(&e.geometry);
            us->cylinder = std::get_if<Cylinder>(&e.geometry);
            us->alpha = e.alpha.get();
            if (e.material < 0) us->mask = kInterfaceMask;
            g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
            rtcSetGeometryUserPrimitiveCount(g, 1);
            rtcSetGeometryUserData(g, us.get());
            rtcSetGeometryBoundsFunction(g, user_bounds, nullptr);
            rtcSetGeometryIntersectFunction(g, user_intersect);
            rtcSetGeometryOccludedFunction(g, user_occluded);
            user = us.get();
            user_shapes.push_back(std::move(us));
        }
        if (masks && e.material < 0) rtcSetGeometryMask(g, kInterfaceMask);
        rtcCommitGeometry(g);
        unsigned id = rtcAttachGeometry(s, g);
        rtcReleaseGeometry(g);
        if (user) user->geom_id = id;  // callbacks run only after the scene is committed
        return id;
    }

    void fill(const RTCRayHit& rh, const Ray& ray, SurfaceHit& h) const {
        int shape;
        const Instance* inst = nullptr;
        h.instance = -1;
        if (rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID) {
            int ii = inst_geom_to_instance[rh.hit.instID[0]];
            inst = &instances[ii];
            h.instance = ii;
            shape = proto_geom_shape[inst->prototype][rh.hit.geomID];
        } else {
            shape = top_geom_shape[rh.hit.geomID];
        }
        const ShapeEntry& e = shapes[shape];
        // Every field of h is written, whatever it held (the path integrator reuses one
        // record per path): the shapes' fills write all but the normal derivatives, which
        // only curved shading normals have.
        h.dndu = h.dndv = h.ss = Vec3(0, 0, 0);
        h.dpdx = h.dpdy = Vec3(0, 0, 0);  // no footprint until the renderer computes one
        h.dudx = h.dvdx = h.dudy = h.dvdy = 0;
        h.t = rh.ray.tfar;
        h.shape = shape;
        h.prim = rh.hit.primID;
        h.material = e.material;
        h.light = -1;
        // Position in the space the shape lives in (world, or the prototype's space).
        Ray r = ray;
        if (inst) {
            Transform inv = inst->world_from_instance.inverse();
            r.o = inv.point(ray.o);
            r.d = inv.vector(ray.d);
        }
        if (const auto* mesh = std::get_if<TriangleMesh>(&e.geometry)) {
            mesh->fill_hit(h.prim, rh.hit.u, rh.hit.v, h);
            if (e.light_offset >= 0) h.light = e.light_offset + int(h.prim);
        } else if (const auto* curves = std::get_if<Curves>(&e.geometry)) {
            curves->fill_hit(h.prim, rh.hit.u, r.o, r.d, h.t, h);  // never emits (builder)
        } else {
            Point3 p_local = r.o + r.d * h.t;
            if (const auto* s = std::get_if<Sphere>(&e.geometry)) {
                Point3 p_obj = s->world_from_object.inverse().point(p_local);
                Float len = length(p_obj);
                if (len > 0) p_obj = p_obj * (s->radius / len);
                s->fill_hit(p_obj, h);
            } else if (const auto* d = std::get_if<Disk>(&e.geometry)) {
                Point3 p_obj = d->world_from_object.inverse().point(p_local);
                p_obj.z = d->height;
                d->fill_hit(p_obj, h);
            } else {
                const Cylinder& c = std::get<Cylinder>(e.geometry);
                Point3 p_obj = c.world_from_object.inverse().point(p_local);
                const Float rr = std::sqrt(sqr(p_obj.x) + sqr(p_obj.y));
                if (rr > 0) {
                    p_obj.x *= c.radius / rr;
                    p_obj.y *= c.radius / rr;
                }
                c.fill_hit(p_obj, h);
            }
            if (e.light_offset >= 0) h.light = e.light_offset;
        }
        if (inst) {
            const Transform& w = inst->world_from_instance;
            Point3 p = w.point(h.p);
            // Conservative error growth through the instance transform.
            const auto& a = w.matrix().m;
            Vec3 err;
            for (int i = 0; i < 3; ++i) {
                double ee = 0;
                for (int j = 0; j < 3; ++j)
                    ee += std::abs(a[i][j]) * (h.p_error[j] + gamma_bound(3) * std::abs(h.p[j]));
                err[i] = Float(ee) + gamma_bound(3) * (std::abs(Float(a[i][3])) + std::abs(p[i]));
            }
            h.p = p;
            h.p_error = err;
            h.ng = normalize(w.normal(h.ng));
            h.ns = normalize(w.normal(h.ns));
            h.dpdu = w.vector(h.dpdu);
            h.ss = Vec3(0, 0, 0);  // recomputed from the transformed dpdu and ns
            h.dpdv = w.vector(h.dpdv);
            h.dndu = w.normal(h.dndu);
            h.dndv = w.normal(h.dndv);
        }
        // The renderer's rays have unit directions (camera rays and BSDF samples), so wo
        // needs no square root and division, which sat on the path's critical chain; other
        // callers' directions are normalised.
        h.wo = -ray.d;
        Float l2 = length_squared(ray.d);
        if (std::abs(l2 - 1) > Float(1e-5)) [[unlikely]]
            h.wo = h.wo / std::sqrt(l2);
    }
};

namespace {

/// Embree's build quality for a scene of these shapes: HIGH (spatial splits, the fastest
/// traversal) up to kHighQualityTriangles triangles. Above, MEDIUM (binned SAH without
/// splits), whose build is several times faster for a traversal a few percent slower; or,
/// when the render is known to trace fewer camera paths than half the scene's triangles,
/// LOW (Embree's Morton builder), whose build is faster still for a slower traversal.
/// Measured 27 Nov 2026 on bench/plygz_load.sh's 10-million-triangle height field (2
/// cores, load average 5-7): the BVH build takes 5.0 CPU-s with MEDIUM and 1.9 with LOW
/// (0.3 microseconds a triangle saved). Renders of it (path tracer, depth 5) take 15-40 %
/// more render CPU time with LOW: 0.94-0.98 against 0.79-0.82 CPU-microseconds a camera
/// path at 390 x 390 and 400 x 400 pixels, 32 spp (bench/plygz_trace.sh); 0.81-0.93
/// against 0.64-0.68 at 550 x 550 and 570 x 570; 12 % at 300 x 300. LOW pays below about
/// 1.5 paths a triangle; the threshold of 0.5 leaves a margin for meshes that Morton codes
/// order worse than a height field, and for longer paths.
constexpr size_t kHighQualityTriangles = 2'000'000;

RTCBuildQuality build_quality(size_t triangles, uint64_t expected_camera_paths) {
    if (triangles <= kHighQualityTriangles) return RTC_BUILD_QUALITY_HIGH;
    if (expected_camera_paths > 0 && expected_camera_paths < triangles / 2)
        return RTC_BUILD_QUALITY_LOW;
    return RTC_BUILD_QUALITY_MEDIUM;
}

}  // namespace

Accel::Accel(const GeometryView& geometry) : m(std::make_unique<Impl>()) {
    auto scene_quality = [&](std::span<const int> shape_ids) {
        size_t tris = 0;
        for (int si : shape_ids)
            if (const auto* mesh = std::get_if<TriangleMesh>(&geometry.shapes[size_t(si)].geometry))
                tris += mesh->num_triangles();
        return build_quality(tris, geometry.expected_camera_paths);
    };
    m->shapes = geometry.shapes.data();
    m->instances = geometry.instances.data();
    m->device = rtcNewDevice("verbose=0");
    if (!m->device) throw Error("could not create the Embree device");
    rtcSetDeviceErrorFunction(m->device, error_callback, nullptr);
    m->masks = rtcGetDeviceProperty(m->device, RTC_DEVICE_PROPERTY_RAY_MASK_SUPPORTED) != 0;

    // Prototypes first: each its own Embree scene, instanced below.
    for (const Prototype& proto : geometry.prototypes) {
        RTCScene ps = rtcNewScene(m->device);
        const RTCBuildQuality quality = scene_quality(proto.shapes);
        rtcSetSceneBuildQuality(ps, quality);
        std::vector<int> map;
        for (int si : proto.shapes) {
            unsigned id = m->attach_shape(ps, si, quality);
            if (map.size() <= id) map.resize(id + 1, -1);
            map[id] = si;
        }
        rtcCommitScene(ps);
        m->proto_scenes.push_back(ps);
        m->proto_geom_shape.push_back(std::move(map));
    }

    m->top = rtcNewScene(m->device);
    const RTCBuildQuality top_quality = scene_quality(geometry.top_level_shapes);
    rtcSetSceneBuildQuality(m->top, top_quality);
    for (int si : geometry.top_level_shapes) {
        unsigned id = m->attach_shape(m->top, si, top_quality);
        if (m->top_geom_shape.size() <= id) m->top_geom_shape.resize(id + 1, -1);
        m->top_geom_shape[id] = si;
    }
    for (size_t ii = 0; ii < geometry.instances.size(); ++ii) {
        const Instance& inst = geometry.instances[ii];
        RTCGeometry g = rtcNewGeometry(m->device, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(g, m->proto_scenes[inst.prototype]);
        float xfm[12];  // 3x4 column-major
        const auto& a = inst.world_from_instance.matrix().m;
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 3; ++r) xfm[c * 3 + r] = float(a[r][c]);
        rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
        rtcCommitGeometry(g);
        unsigned id = rtcAttachGeometry(m->top, g);
        rtcReleaseGeometry(g);
        if (m->inst_geom_to_instance.size() <= id) m->inst_geom_to_instance.resize(id + 1, -1);
        m->inst_geom_to_instance[id] = int(ii);
        if (m->top_geom_shape.size() <= id) m->top_geom_shape.resize(id + 1, -1);
    }
    rtcCommitScene(m->top);
}

Accel::~Accel() {
    if (m->top) rtcReleaseScene(m->top);
    for (RTCScene s : m->proto_scenes) rtcReleaseScene(s);
    if (m->device) rtcReleaseDevice(m->device);
}

bool Accel::intersect(const Ray& ray, SurfaceHit& h) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = ray.o.x;
    rh.ray.org_y = ray.o.y;
    rh.ray.org_z = ray.o.z;
    rh.ray.dir_x = ray.d.x;
    rh.ray.dir_y = ray.d.y;
    rh.ray.dir_z = ray.d.z;
    rh.ray.tnear = 0;
    rh.ray.tfar = ray.t_max;
    rh.ray.time = 0;
    rh.ray.mask = 0xFFFFFFFF;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(m->top, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    m->fill(rh, ray, h);
    return true;
}

unsigned Accel::intersect_packet(const Ray* rays, unsigned active, SurfaceHit* hits) const {
    static_assert(kPacket == 8, "rtcIntersect8");
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(32) RTCRayHit8 rh;
    alignas(32) int valid[8];
    put_packet(rays, active, valid, rh.ray);
    for (int i = 0; i < 8; ++i) {
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    rtcIntersect8(valid, m->top, &ctx, &rh);
    unsigned hit_mask = 0;
    for (int i = 0; i < 8; ++i) {
        if (!((active >> i) & 1) || rh.hit.geomID[i] == RTC_INVALID_GEOMETRY_ID) continue;
        RTCRayHit one;
        one.ray.tfar = rh.ray.tfar[i];
        one.hit.u = rh.hit.u[i];
        one.hit.v = rh.hit.v[i];
        one.hit.primID = rh.hit.primID[i];
        one.hit.geomID = rh.hit.geomID[i];
        one.hit.instID[0] = rh.hit.instID[0][i];
        m->fill(one, rays[i], hits[i]);
        hit_mask |= 1u << i;
    }
    return hit_mask;
}

unsigned Accel::occluded_packet_masked(const Ray* rays, unsigned active, unsigned mask) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(32) RTCRay8 r8;
    alignas(32) int valid[8];
    put_packet(rays, active, valid, r8);
    for (int i = 0; i < 8; ++i) r8.mask[i] = mask;
    rtcOccluded8(valid, m->top, &ctx, &r8);
    unsigned blocked = 0;
    for (int i = 0; i < 8; ++i)
        if (((active >> i) & 1) && r8.tfar[i] < 0) blocked |= 1u << i;
    return blocked;
}

bool Accel::occluded(const Ray& ray) const { return occluded_masked(ray, 0xFFFFFFFFu); }

bool Accel::occluded_by_surface(const Ray& ray) const {
    if (m->masks) return occluded_masked(ray, kScatteringBit);
    // Without ray masks: step through the interfaces along the ray.
    Ray r = ray;
    SurfaceHit h;
    for (int crossings = 0; crossings < 256; ++crossings) {
        if (!intersect(r, h)) return false;
        if (h.material >= 0) return true;
        const Float t = h.t * (1 + Float(1e-5)) + Float(1e-7);
        if (!(t < r.t_max)) return false;
        r.o = r.o + r.d * t;
        r.t_max -= t;
    }
    return true;
}

unsigned Accel::occluded_by_surface_packet(const Ray* rays, unsigned active) const {
    if (!m->masks) {
        unsigned blocked = 0;
        for (int i = 0; i < kPacket; ++i)
            if (((active >> i) & 1) && occluded_by_surface(rays[i])) blocked |= 1u << i;
        return blocked;
    }
    return occluded_packet_masked(rays, active, kScatteringBit);
}

unsigned Accel::occluded_packet(const Ray* rays, unsigned active) const {
    return occluded_packet_masked(rays, active, 0xFFFFFFFFu);
}

bool Accel::occluded_masked(const Ray& ray, unsigned mask) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r;
    r.org_x = ray.o.x;
    r.org_y = ray.o.y;
    r.org_z = ray.o.z;
    r.dir_x = ray.d.x;
    r.dir_y = ray.d.y;
    r.dir_z = ray.d.z;
    r.tnear = 0;
    r.tfar = ray.t_max;
    r.time = 0;
    r.mask = mask;
    r.id = 0;
    r.flags = 0;
    rtcOccluded1(m->top, &ctx, &r);
    return r.tfar < 0;
}

Bounds3 Accel::bounds() const {
    RTCBounds b;
    rtcGetSceneBounds(m->top, &b);
    Bounds3 r;
    r.lo = Vec3(b.lower_x, b.lower_y, b.lower_z);
    r.hi = Vec3(b.upper_x, b.upper_y, b.upper_z);
    return r;
}

}  // namespace sr
