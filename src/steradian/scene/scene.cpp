#include "steradian/scene/scene.h"

#include "steradian/accel/accel.h"

namespace sr {

Scene::Scene() = default;
Scene::~Scene() = default;
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

void Scene::finalize_geometry(uint64_t expected_camera_paths) {
    for (ShapeEntry& e : shapes)
        if (auto* mesh = std::get_if<TriangleMesh>(&e.geometry)) mesh->cache_flat_frames();
    m_accel = std::make_unique<Accel>(
        GeometryView{shapes, top_level_shapes, prototypes, instances, expected_camera_paths});
    bounds = m_accel->bounds();
}

void Scene::finalize_lights() {
    light_sampler.build(lights, integrator.light_sampler == "power"     ? LightSamplerKind::Power
                                : integrator.light_sampler == "uniform" ? LightSamplerKind::Uniform
                                                                        : LightSamplerKind::InfiniteShare);
}

bool Scene::intersect(const Ray& ray, SurfaceHit& h) const { return m_accel->intersect(ray, h); }

bool Scene::occluded(const Ray& ray) const { return m_accel->occluded(ray); }

unsigned Scene::intersect_packet(const Ray* rays, unsigned active, SurfaceHit* hits) const {
    static_assert(kRayPacket == Accel::kPacket);
    return m_accel->intersect_packet(rays, active, hits);
}

unsigned Scene::occluded_packet(const Ray* rays, unsigned active) const {
    return m_accel->occluded_packet(rays, active);
}

bool Scene::occluded_by_surface(const Ray& ray) const { return m_accel->occluded_by_surface(ray); }

unsigned Scene::occluded_by_surface_packet(const Ray* rays, unsigned active) const {
    return m_accel->occluded_by_surface_packet(rays, active);
}

Occluder::Occluder(const GeometryView& geometry) : m_accel(std::make_unique<Accel>(geometry)) {}
Occluder::~Occluder() = default;

bool Occluder::occluded(const Ray& ray) const { return m_accel->occluded(ray); }

unsigned Occluder::occluded_packet(const Ray* rays, unsigned active) const {
    return m_accel->occluded_packet(rays, active);
}

bool Occluder::occluded_by_surface(const Ray& ray) const { return m_accel->occluded_by_surface(ray); }

unsigned Occluder::occluded_by_surface_packet(const Ray* rays, unsigned active) const {
    return m_accel->occluded_by_surface_packet(rays, active);
}

}  // namespace sr
