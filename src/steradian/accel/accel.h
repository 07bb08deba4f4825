#pragma once
/// Ray queries through Embree 3. This header does not include Embree; accel.cpp is the
/// only translation unit that does.
#include <memory>

#include "steradian/geometry/hit.h"
#include "steradian/geometry/scene_geometry.h"

namespace sr {

class Accel {
public:
    /// Builds Embree scenes for the top level and every prototype of `geometry`, sharing
    /// the meshes' vertex and index buffers. The vectors the view refers to must outlive the
    /// Accel (their heap buffers, not the objects holding them: a Scene may be moved).
    explicit Accel(const GeometryView& geometry);
    ~Accel();
    Accel(const Accel&) = delete;
    Accel& operator=(const Accel&) = delete;

    bool intersect(const Ray& ray, SurfaceHit& h) const;
    bool occluded(const Ray& ray) const;
    /// Closest hits of up to kPacket rays (rays[i] for the bits i set in `active`) traced as
    /// one Embree packet; returns the bits of the rays that hit, whose hits[i] are filled as
    /// intersect() fills them. Meant for coherent rays (a pixel's camera rays), for which it
    /// costs much less than one intersect() per ray.
    static constexpr int kPacket = 8;
    unsigned intersect_packet(const Ray* rays, unsigned active, SurfaceHit* hits) const;
    /// occluded() for up to kPacket rays (the bits of `active`) as one packet; returns the
    /// bits of the rays that are blocked.
    unsigned occluded_packet(const Ray* rays, unsigned active) const;
    /// occluded() by a surface that scatters: an interface (a shape without a material: a
    /// luminous opening, a medium boundary) lets the ray through (Embree's ray masks; where
    /// the Embree build lacks them, by stepping through the interfaces).
    bool occluded_by_surface(const Ray& ray) const;
    unsigned occluded_by_surface_packet(const Ray* rays, unsigned active) const;
    Bounds3 bounds() const;

private:
    bool occluded_masked(const Ray& ray, unsigned mask) const;
    unsigned occluded_packet_masked(const Ray* rays, unsigned active, unsigned mask) const;
    struct Impl;
    std::unique_ptr<Impl> m;
};

}  // namespace sr
