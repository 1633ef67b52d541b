#include "scene/meshes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

namespace envshadow {
namespace {

constexpr float kPi = glm::pi<float>();

// Deterministic on every platform (std distributions are not): splitmix64.
class Random {
public:
    explicit Random(std::uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull) {}
    float uniform(float lo, float hi) { return lo + (hi - lo) * float(next() >> 40) * (1.0f / 16777216.0f); }
    glm::vec3 direction() {
        const float y = uniform(-1.0f, 1.0f);
        const float phi = uniform(0.0f, 2.0f * kPi);
        const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
        return {r * std::cos(phi), y, r * std::sin(phi)};
    }

private:
    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    std::uint64_t state_;
};

// Geodesic sphere: the icosahedron with every face cut into f^2 triangles, vertices pushed onto the
// unit sphere and shared between faces (so the result is closed).
struct Geodesic {
    std::vector<glm::vec3> directions;
    std::vector<std::uint32_t> indices;
};

Geodesic make_geodesic(int frequency) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    const std::array<glm::vec3, 12> corners = {glm::vec3(-1, t, 0),  glm::vec3(1, t, 0),   glm::vec3(-1, -t, 0),
                                               glm::vec3(1, -t, 0),  glm::vec3(0, -1, t),  glm::vec3(0, 1, t),
                                               glm::vec3(0, -1, -t), glm::vec3(0, 1, -t),  glm::vec3(t, 0, -1),
                                               glm::vec3(t, 0, 1),   glm::vec3(-t, 0, -1), glm::vec3(-t, 0, 1)};
    std::array<std::array<std::uint32_t, 3>, 20> faces = {{{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                                           {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                                           {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                                           {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}}};
    for (auto& face : faces) {  // counter-clockwise seen from outside
        const glm::vec3 &a = corners[face[0]], &b = corners[face[1]], &c = corners[face[2]];
        if (glm::dot(glm::cross(b - a, c - a), a) < 0.0f) std::swap(face[1], face[2]);
    }

    const std::uint64_t f = std::uint64_t(frequency);
    Geodesic g;
    g.directions.reserve(10 * f * f + 2);
    g.indices.reserve(60 * f * f);
    std::unordered_map<std::uint64_t, std::uint32_t> vertex_of_key;
    vertex_of_key.reserve(10 * f * f + 2);

    auto vertex = [&](std::uint64_t face_index, std::uint64_t a, std::uint64_t b) -> std::uint32_t {
        const auto& face = faces[face_index];
        const std::array<std::uint64_t, 3> weights = {f - a - b, a, b};
        // A vertex on an edge or corner is keyed by the icosahedron corners it lies between, so that
        // both faces sharing the edge find the same vertex.
        std::uint64_t key;
        std::array<int, 3> nonzero{};
        int count = 0;
        for (int k = 0; k < 3; ++k)
            if (weights[k] != 0) nonzero[count++] = k;
        if (count == 1) {
            key = (0ull << 62) | face[nonzero[0]];
        } else if (count == 2) {
            int lo = nonzero[0], hi = nonzero[1];
            if (face[lo] > face[hi]) std::swap(lo, hi);
            key = (1ull << 62) | (std::uint64_t(face[lo]) << 40) | (std::uint64_t(face[hi]) << 20) | weights[hi];
        } else {
            key = (2ull << 62) | (face_index << 40) | (a << 20) | b;
        }
        const auto [it, inserted] = vertex_of_key.try_emplace(key, std::uint32_t(g.directions.size()));
        if (inserted) {
            glm::vec3 p(0.0f);
            for (int k = 0; k < 3; ++k) p += float(weights[k]) * corners[face[k]];
            g.directions.push_back(glm::normalize(p));
        }
        return it->second;
    };

    for (std::uint64_t fi = 0; fi < faces.size(); ++fi) {
        for (std::uint64_t a = 0; a < f; ++a) {
            for (std::uint64_t b = 0; a + b < f; ++b) {
                const std::uint32_t p = vertex(fi, a, b), q = vertex(fi, a + 1, b), r = vertex(fi, a, b + 1);
                g.indices.insert(g.indices.end(), {p, q, r});
                if (a + b + 1 < f) {
                    const std::uint32_t s = vertex(fi, a + 1, b + 1);
                    g.indices.insert(g.indices.end(), {q, s, r});
                }
            }
        }
    }
    return g;
}

// Smooth bump of height 1 at `axis`, falling off with the angle like a Gaussian of width `sigma`.
float lobe(const glm::vec3& direction, const glm::vec3& axis, float sigma) {
    const float angle = std::acos(std::clamp(glm::dot(direction, axis), -1.0f, 1.0f));
    return std::exp(-angle * angle / (2.0f * sigma * sigma));
}

void append(Mesh& mesh, const Mesh& part) {
    const auto base = std::uint32_t(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), part.positions.begin(), part.positions.end());
    mesh.normals.insert(mesh.normals.end(), part.normals.begin(), part.normals.end());
    for (const std::uint32_t i : part.indices) mesh.indices.push_back(base + i);
}

// Two unit vectors perpendicular to `axis` and to each other, with tangent x bitangent = axis.
void frame_around(const glm::vec3& axis, glm::vec3& tangent, glm::vec3& bitangent) {
    const glm::vec3 helper = std::abs(axis.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    tangent = glm::normalize(glm::cross(helper, axis));
    bitangent = glm::cross(axis, tangent);
}

// Closed tapered tube from `bottom` to `top` (a frustum with fan caps sharing the rim vertices).
Mesh make_stalk(const glm::vec3& bottom, const glm::vec3& top, float bottom_radius, float top_radius, int sides) {
    const glm::vec3 axis = glm::normalize(top - bottom);
    glm::vec3 tangent, bitangent;
    frame_around(axis, tangent, bitangent);
    Mesh m;
    for (int ring = 0; ring < 2; ++ring) {
        const glm::vec3 centre = ring == 0 ? bottom : top;
        const float radius = ring == 0 ? bottom_radius : top_radius;
        for (int k = 0; k < sides; ++k) {
            const float phi = 2.0f * kPi * float(k) / float(sides);
            m.positions.push_back(centre + radius * (std::cos(phi) * tangent + std::sin(phi) * bitangent));
        }
    }
    const auto bottom_centre = std::uint32_t(m.positions.size());
    m.positions.push_back(bottom);
    m.positions.push_back(top);
    const std::uint32_t top_centre = bottom_centre + 1;
    const auto n = std::uint32_t(sides);
    for (std::uint32_t k = 0; k < n; ++k) {
        const std::uint32_t k1 = (k + 1) % n;
        // Around the axis the angle grows counter-clockwise seen from the top, so the side quads run
        // bottom k -> bottom k1 -> top k1 -> top k seen from outside.
        m.indices.insert(m.indices.end(), {k, k1, n + k1, k, n + k1, n + k});
        m.indices.insert(m.indices.end(), {bottom_centre, k1, k});
        m.indices.insert(m.indices.end(), {top_centre, n + k, n + k1});
    }
    return m;
}

}  // namespace

int geodesic_frequency(int triangles) {
    int best = 1;
    for (int f = 1; 20ll * f * f <= 4ll * std::max(triangles, 20); ++f)
        if (std::llabs(20ll * f * f - triangles) < std::llabs(20ll * best * best - triangles)) best = f;
    return best;
}

void compute_vertex_normals(Mesh& mesh) {
    std::vector<glm::vec3> sum(mesh.positions.size(), glm::vec3(0.0f));
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
        // The cross product's length is twice the area: the weighting comes for free.
        const glm::vec3 n = glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
        sum[a] += n;
        sum[b] += n;
        sum[c] += n;
    }
    mesh.normals.resize(mesh.positions.size());
    for (std::size_t i = 0; i < sum.size(); ++i) {
        const float length = glm::length(sum[i]);
        mesh.normals[i] = length > 0.0f && std::isfinite(length) ? sum[i] / length : glm::vec3(0.0f, 1.0f, 0.0f);
    }
}

void compute_vertex_tangents(Mesh& mesh) {
    std::vector<glm::vec3> along_u(mesh.positions.size(), glm::vec3(0.0f)), along_v(along_u);
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
        const glm::vec3 e1 = mesh.positions[b] - mesh.positions[a], e2 = mesh.positions[c] - mesh.positions[a];
        const glm::vec2 d1 = mesh.texcoords[b] - mesh.texcoords[a], d2 = mesh.texcoords[c] - mesh.texcoords[a];
        // e = dP/du du + dP/dv dv for both edges, solved for the gradients; multiplied by |det| instead of
        // divided by det, so that a sliver of uv does not outweigh its neighbours.
        const float det = d1.x * d2.y - d2.x * d1.y;
        if (!(std::abs(det) > 0.0f) || !std::isfinite(det)) continue;
        const float sign = det > 0.0f ? 1.0f : -1.0f;
        const glm::vec3 u = sign * (e1 * d2.y - e2 * d1.y), v = sign * (e2 * d1.x - e1 * d2.x);
        for (const std::uint32_t i : {a, b, c}) {
            along_u[i] += u;
            along_v[i] += v;
        }
    }
    mesh.tangents.resize(mesh.positions.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const glm::vec3 n = mesh.normals[i];
        glm::vec3 t = along_u[i] - n * glm::dot(n, along_u[i]);
        float length = glm::length(t);
        if (!(length > 1e-12f) || !std::isfinite(length)) {  // no gradient: any direction in the plane
            t = glm::cross(n, std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0));
            length = glm::length(t);
        }
        t /= length;
        // glTF's v runs down the image and a normal map's +y points up it: the bitangent along -v.
        const float w = glm::dot(glm::cross(n, t), along_v[i]) > 0.0f ? -1.0f : 1.0f;
        mesh.tangents[i] = glm::vec4(t, w);
    }
}

glm::vec4 transform_tangent(const glm::dmat3& linear, const glm::vec4& tangent, const glm::dvec3& normal) {
    glm::dvec3 t = linear * glm::dvec3(tangent);
    t -= normal * glm::dot(normal, t);
    const double length = glm::length(t);
    const float w = glm::determinant(linear) < 0.0 ? -tangent.w : tangent.w;
    return glm::vec4(length > 1e-30 && std::isfinite(length) ? glm::vec3(t / length) : glm::vec3(0.0f), w);
}

Mesh make_mesh(const PlaneShape& shape) {
    const float h = 0.5f * shape.size;
    Mesh m;
    m.positions = {{-h, 0, -h}, {-h, 0, h}, {h, 0, h}, {h, 0, -h}};
    m.normals.assign(4, glm::vec3(0, 1, 0));
    m.indices = {0, 1, 2, 0, 2, 3};
    m.compute_bounds();
    return m;
}

Mesh make_mesh(const SphereShape& shape) {
    const int segments = shape.segments;
    const int bands = std::max(2, segments / 2);
    Mesh m;
    // Pole, rings 1 .. bands-1 of `segments` vertices, pole. theta from +Y, phi turning +X towards +Z.
    m.normals.push_back({0, 1, 0});
    for (int i = 1; i < bands; ++i) {
        const float theta = kPi * float(i) / float(bands);
        for (int j = 0; j < segments; ++j) {
            const float phi = 2.0f * kPi * float(j) / float(segments);
            m.normals.push_back({std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)});
        }
    }
    m.normals.push_back({0, -1, 0});
    for (const glm::vec3& n : m.normals) m.positions.push_back(shape.radius * n);

    const auto s = std::uint32_t(segments);
    const auto ring = [s](int i, std::uint32_t j) { return 1 + std::uint32_t(i - 1) * s + j % s; };
    const auto south = std::uint32_t(m.positions.size() - 1);
    for (std::uint32_t j = 0; j < s; ++j) m.indices.insert(m.indices.end(), {0, ring(1, j + 1), ring(1, j)});
    for (int i = 1; i + 1 < bands; ++i) {
        for (std::uint32_t j = 0; j < s; ++j) {
            const std::uint32_t u0 = ring(i, j), u1 = ring(i, j + 1), l0 = ring(i + 1, j), l1 = ring(i + 1, j + 1);
            m.indices.insert(m.indices.end(), {u0, u1, l1, u0, l1, l0});
        }
    }
    for (std::uint32_t j = 0; j < s; ++j)
        m.indices.insert(m.indices.end(), {south, ring(bands - 1, j), ring(bands - 1, j + 1)});
    m.compute_bounds();
    return m;
}

Mesh make_mesh(const TorusShape& shape) {
    const auto segments = std::uint32_t(shape.segments), sides = std::uint32_t(shape.sides);
    Mesh m;
    for (std::uint32_t i = 0; i < segments; ++i) {
        const float phi = 2.0f * kPi * float(i) / float(segments);
        for (std::uint32_t j = 0; j < sides; ++j) {
            const float theta = 2.0f * kPi * float(j) / float(sides);
            const glm::vec3 n(std::cos(theta) * std::cos(phi), std::sin(theta), std::cos(theta) * std::sin(phi));
            const glm::vec3 centre(std::cos(phi), 0.0f, std::sin(phi));
            m.positions.push_back(shape.major_radius * centre + shape.minor_radius * n);
            m.normals.push_back(n);
        }
    }
    const auto at = [&](std::uint32_t i, std::uint32_t j) { return (i % segments) * sides + j % sides; };
    for (std::uint32_t i = 0; i < segments; ++i) {
        for (std::uint32_t j = 0; j < sides; ++j) {
            // d/dtheta x d/dphi points out of the tube.
            const std::uint32_t a = at(i, j), b = at(i, j + 1), c = at(i + 1, j + 1), d = at(i + 1, j);
            m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
        }
    }
    m.compute_bounds();
    return m;
}

Mesh make_mesh(const BoxShape& shape) {
    const glm::vec3 h = 0.5f * shape.size;
    // Each face: normal n and in-plane axes u, v with u x v = n, so corners -u-v, +u-v, +u+v, -u+v run
    // counter-clockwise seen from outside.
    const glm::vec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
    const std::array<std::array<glm::vec3, 3>, 6> faces = {
        {{x, y, z}, {-x, z, y}, {y, z, x}, {-y, x, z}, {z, x, y}, {-z, y, x}}};
    Mesh m;
    for (const auto& [n, u, v] : faces) {
        const auto base = std::uint32_t(m.positions.size());
        for (const glm::vec2 s : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
            m.positions.push_back(h * (n + s.x * u + s.y * v));
            m.normals.push_back(n);
        }
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    m.compute_bounds();
    return m;
}

Mesh make_mesh(const BlobShape& shape) {
    const Geodesic g = make_geodesic(geodesic_frequency(shape.triangles));
    struct Bump {
        glm::vec3 axis;
        float height, width;
    };
    Random random(shape.seed);
    std::vector<Bump> bumps(14);
    for (Bump& b : bumps) b = {random.direction(), random.uniform(-0.5f, 1.0f), random.uniform(0.25f, 0.6f)};

    Mesh m;
    m.indices = g.indices;
    m.positions.reserve(g.directions.size());
    for (const glm::vec3& d : g.directions) {
        float r = 1.0f;
        for (const Bump& b : bumps) r += shape.lumpiness * b.height * lobe(d, b.axis, b.width);
        m.positions.push_back(shape.radius * std::max(r, 0.2f) * d);
    }
    compute_vertex_normals(m);
    m.compute_bounds();
    return m;
}

Mesh make_mesh(const FigureShape& shape) {
    // A mannequin of overlapping closed ellipsoids, in metres for a 1.8 m figure (scaled at the end).
    struct Part {
        glm::vec3 centre, radii;
        glm::vec3 axis{0.0f, 1.0f, 0.0f};  // direction of radii.y
    };
    std::vector<Part> parts = {
        {{0.0f, 1.15f, 0.0f}, {0.22f, 0.33f, 0.15f}},    // chest
        {{0.0f, 0.88f, 0.0f}, {0.19f, 0.14f, 0.13f}},    // hips
        {{0.0f, 1.47f, 0.0f}, {0.06f, 0.09f, 0.06f}},    // neck
        {{0.0f, 1.62f, 0.02f}, {0.12f, 0.14f, 0.13f}},   // head
        {{0.0f, 1.60f, 0.14f}, {0.04f, 0.035f, 0.05f}},  // snout
    };
    // A limb segment from a to b: an ellipsoid reaching a little past both ends so that joints overlap.
    const auto limb = [&](glm::vec3 a, glm::vec3 b, float radius) {
        const float half = 0.5f * glm::distance(a, b) + 0.5f * radius;
        parts.push_back({0.5f * (a + b), {radius, half, radius}, glm::normalize(b - a)});
    };
    for (const float side : {-1.0f, 1.0f}) {
        const auto at = [side](float x, float y, float z) { return glm::vec3(side * x, y, z); };
        parts.push_back(
            {at(0.08f, 1.80f, 0.0f), {0.035f, 0.09f, 0.02f}, glm::normalize(at(0.35f, 1.0f, 0.0f))});  // ear
        limb(at(0.25f, 1.36f, 0.0f), at(0.40f, 1.08f, 0.06f), 0.065f);                                 // upper arm
        limb(at(0.40f, 1.08f, 0.06f), at(0.46f, 0.84f, 0.18f), 0.05f);                                 // forearm
        parts.push_back({at(0.47f, 0.80f, 0.20f), {0.05f, 0.07f, 0.04f}});                             // hand
        limb(at(0.10f, 0.86f, 0.0f), at(0.13f, 0.48f, 0.03f), 0.09f);                                  // thigh
        limb(at(0.13f, 0.48f, 0.03f), at(0.14f, 0.09f, 0.0f), 0.065f);                                 // shin
        parts.push_back({at(0.14f, 0.04f, 0.06f), {0.06f, 0.04f, 0.12f}});  // foot, touching y = 0
    }

    // Triangles shared out by surface area (Thomsen's ellipsoid approximation), then frequencies
    // nudged one step at a time while that brings the total nearer the target.
    std::vector<double> share(parts.size());
    double total_area = 0.0;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const double a = std::pow(parts[i].radii.x, 1.6), b = std::pow(parts[i].radii.y, 1.6),
                     c = std::pow(parts[i].radii.z, 1.6);
        share[i] = std::pow((a * b + a * c + b * c) / 3.0, 1.0 / 1.6);
        total_area += share[i];
    }
    std::vector<int> frequency(parts.size());
    long long total = 0;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        frequency[i] = std::max(2, geodesic_frequency(int(std::lround(shape.triangles * share[i] / total_area))));
        total += 20ll * frequency[i] * frequency[i];
    }
    for (bool improved = true; improved;) {
        improved = false;
        std::size_t best_part = 0;
        int best_step = 0;
        long long best_error = std::llabs(total - shape.triangles);
        for (std::size_t i = 0; i < parts.size(); ++i) {
            for (const int step : {-1, 1}) {
                const int f = frequency[i] + step;
                if (f < 2) continue;
                const long long changed = total + 20ll * (f * f - frequency[i] * frequency[i]);
                if (std::llabs(changed - shape.triangles) < best_error) {
                    best_error = std::llabs(changed - shape.triangles);
                    best_part = i;
                    best_step = step;
                }
            }
        }
        if (best_step != 0) {
            const int f = frequency[best_part];
            total += 20ll * ((f + best_step) * (f + best_step) - f * f);
            frequency[best_part] += best_step;
            improved = true;
        }
    }

    Mesh m;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const Part& part = parts[i];
        // Right-handed frame with the ellipsoid's y radius along part.axis (so faces stay outward).
        const glm::vec3 y = part.axis;
        const glm::vec3 x =
            std::abs(y.z) < 0.9f ? glm::normalize(glm::cross(y, glm::vec3(0, 0, 1))) : glm::vec3(1, 0, 0);
        const glm::vec3 z = glm::cross(x, y);
        const glm::mat3 shape_from_unit(x * part.radii.x, y * part.radii.y, z * part.radii.z);
        const Geodesic g = make_geodesic(frequency[i]);
        Mesh piece;
        piece.indices = g.indices;
        for (const glm::vec3& d : g.directions) piece.positions.push_back(part.centre + shape_from_unit * d);
        append(m, piece);
    }
    m.compute_bounds();
    // Feet on y = 0, centred on the Y axis, `height` tall.
    const float scale = shape.height / (m.bounds_max.y - m.bounds_min.y);
    const glm::vec3 offset(-0.5f * (m.bounds_min.x + m.bounds_max.x), -m.bounds_min.y,
                           -0.5f * (m.bounds_min.z + m.bounds_max.z));
    for (glm::vec3& p : m.positions) p = scale * (p + offset);
    compute_vertex_normals(m);
    m.compute_bounds();
    return m;
}

Mesh make_mesh(const VirusShape& shape) {
    Mesh m;
    const Geodesic body = make_geodesic(shape.detail);
    m.indices = body.indices;
    for (const glm::vec3& d : body.directions) m.positions.push_back(shape.radius * d);

    const Geodesic knob = make_geodesic(2);
    const float golden_angle = kPi * (3.0f - std::sqrt(5.0f));
    const float length = shape.spike_length;
    for (int k = 0; k < shape.spikes; ++k) {
        // Fibonacci spiral: evenly spread directions.
        const float y = 1.0f - (2.0f * float(k) + 1.0f) / float(shape.spikes);
        const float ring = std::sqrt(std::max(0.0f, 1.0f - y * y));
        const float phi = golden_angle * float(k);
        const glm::vec3 d(ring * std::cos(phi), y, ring * std::sin(phi));
        // The stalk starts inside the body and ends at the knob's centre, so no seam shows.
        const glm::vec3 tip = (shape.radius + length) * d;
        append(m, make_stalk(0.85f * shape.radius * d, tip, 0.22f * length, 0.12f * length, 8));
        Mesh ball;
        ball.indices = knob.indices;
        for (const glm::vec3& kd : knob.directions) ball.positions.push_back(tip + 0.3f * length * kd);
        append(m, ball);
    }
    compute_vertex_normals(m);
    m.compute_bounds();
    return m;
}

}  // namespace envshadow
