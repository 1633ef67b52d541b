#pragma once
// Geometric properties the scene tests check on any Mesh, computed from the triangles alone.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <tuple>
#include <vector>

#include <glm/geometric.hpp>

#include "scene/scene.h"

namespace envshadow::test {

// Triangles whose directed edges, after welding vertices with bit-identical positions, do not pair
// up exactly (each undirected edge used once in each direction). 0 for a closed, consistently
// oriented surface.
inline std::size_t unpaired_edges(const Mesh& mesh) {
    using Key = std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>;
    std::map<Key, std::uint32_t> welded;
    std::vector<std::uint32_t> id(mesh.positions.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        Key key;
        std::memcpy(&std::get<0>(key), &mesh.positions[i].x, 4);
        std::memcpy(&std::get<1>(key), &mesh.positions[i].y, 4);
        std::memcpy(&std::get<2>(key), &mesh.positions[i].z, 4);
        id[i] = welded.try_emplace(key, std::uint32_t(welded.size())).first->second;
    }
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) ++directed[{id[mesh.indices[t + k]], id[mesh.indices[t + (k + 1) % 3]]}];
    std::size_t bad = 0;
    for (const auto& [edge, count] : directed) {
        const auto reverse = directed.find({edge.second, edge.first});
        if (count != 1 || reverse == directed.end() || reverse->second != 1) ++bad;
    }
    return bad;
}

// Signed volume enclosed by the triangles (divergence theorem): positive when faces point outwards.
inline double signed_volume(const Mesh& mesh) {
    double v = 0.0;
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
        const glm::dvec3 a(mesh.positions[mesh.indices[t]]), b(mesh.positions[mesh.indices[t + 1]]),
            c(mesh.positions[mesh.indices[t + 2]]);
        v += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    return v;
}

inline glm::dvec3 face_normal(const Mesh& mesh, std::size_t t) {
    const glm::dvec3 a(mesh.positions[mesh.indices[t]]), b(mesh.positions[mesh.indices[t + 1]]),
        c(mesh.positions[mesh.indices[t + 2]]);
    return glm::cross(b - a, c - a);
}

// Largest | |n| - 1 | over the vertex normals.
inline double worst_normal_length_error(const Mesh& mesh) {
    double worst = 0.0;
    for (const glm::vec3& n : mesh.normals) worst = std::max(worst, std::abs(double(glm::length(n)) - 1.0));
    return worst;
}

// Triangle corners whose vertex normal points against the triangle's own facing.
inline std::size_t normals_against_faces(const Mesh& mesh) {
    std::size_t against = 0;
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
        const glm::dvec3 f = face_normal(mesh, t);
        if (glm::length(f) < 1e-12) continue;
        for (int k = 0; k < 3; ++k)
            if (glm::dot(f, glm::dvec3(mesh.normals[mesh.indices[t + k]])) <= 0.0) ++against;
    }
    return against;
}

}  // namespace envshadow::test
