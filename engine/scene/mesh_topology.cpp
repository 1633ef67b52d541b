#include "scene/mesh_topology.h"

#include <algorithm>
#include <vector>

#include <meshoptimizer.h>

namespace envshadow {

bool is_closed(std::span<const std::uint32_t> indices) {
    if (indices.empty() || indices.size() % 3 != 0) return false;
    // Each vertex's outgoing edges in one array (a counting sort): linear time, 4 bytes an edge. A
    // level of a large mesh uses few of its vertices: those are numbered densely first.
    const std::uint32_t largest = *std::max_element(indices.begin(), indices.end());
    std::vector<std::uint32_t> renumbered;
    std::size_t vertex_count = std::size_t(largest) + 1;
    if (vertex_count > indices.size()) {
        std::vector<std::uint32_t> used(indices.begin(), indices.end());
        std::sort(used.begin(), used.end());
        used.erase(std::unique(used.begin(), used.end()), used.end());
        renumbered.resize(indices.size());
        for (std::size_t i = 0; i < indices.size(); ++i)
            renumbered[i] = std::uint32_t(std::lower_bound(used.begin(), used.end(), indices[i]) - used.begin());
        vertex_count = used.size();
    }
    const std::span<const std::uint32_t> local = renumbered.empty() ? indices : renumbered;
    std::vector<std::uint32_t> first(vertex_count + 1, 0), to(local.size());
    for (std::uint32_t v : local) ++first[v + 1];
    for (std::size_t v = 0; v < vertex_count; ++v) first[v + 1] += first[v];
    {
        std::vector<std::uint32_t> next(first.begin(), first.end() - 1);
        for (std::size_t t = 0; t < local.size(); t += 3)
            for (std::size_t e = 0; e < 3; ++e) to[next[local[t + e]]++] = local[t + (e + 1) % 3];
    }
    for (std::size_t v = 0; v < vertex_count; ++v)
        std::sort(to.begin() + std::ptrdiff_t(first[v]), to.begin() + std::ptrdiff_t(first[v + 1]));
    // Every directed edge (a, b) once, not degenerate, and its reverse (b, a) once.
    for (std::uint32_t a = 0; a < vertex_count; ++a)
        for (std::uint32_t i = first[a]; i < first[a + 1]; ++i) {
            const std::uint32_t b = to[i];
            if (a == b || (i + 1 < first[a + 1] && to[i + 1] == b)) return false;
            const auto back =
                std::equal_range(to.begin() + std::ptrdiff_t(first[b]), to.begin() + std::ptrdiff_t(first[b + 1]), a);
            if (back.second - back.first != 1) return false;
        }
    return true;
}

bool is_closed_surface(const Mesh& mesh) {
    if (mesh.indices.empty() || mesh.positions.empty()) return false;
    std::vector<std::uint32_t> welded(mesh.indices.size());
    meshopt_generateShadowIndexBuffer(welded.data(), mesh.indices.data(), mesh.indices.size(), &mesh.positions[0].x,
                                      mesh.positions.size(), sizeof(glm::vec3), sizeof(glm::vec3));
    return is_closed(welded);
}

}  // namespace envshadow
