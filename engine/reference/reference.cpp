#include "reference/reference.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec4.hpp>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include "core/error.h"
#include "env/brdf.h"
#include "env/gltf_brdf.h"
#include "env/latlong.h"
#include "env/shading_normal.h"
#include "reference/environment_sampler.h"
#include "reference/ray_tracer.h"

namespace envshadow::reference {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kPilotRounds = 8;      // rounds that only plan how many rounds a pixel needs
constexpr int kMinRounds = 16;       // the reported standard error has at least 15 degrees of freedom
constexpr double kPlanMargin = 1.5;  // rounds planned for 1.5x the pilot's variance
constexpr int kGrid = 6;             // per pilot round, 6 x 6 jittered samples of each strategy in use
constexpr int kLargestGrid = 24;     // rounds of hard pixels use up to 24 x 24 (stratification pays more)

// xoshiro256** seeded through splitmix64: independent streams per pixel, whatever the thread order.
class Random {
public:
    explicit Random(std::uint64_t seed) {
        for (std::uint64_t& word : state_) {
            seed += 0x9e3779b97f4a7c15ull;
            std::uint64_t z = seed;
            z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
            z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
            word = z ^ (z >> 31);
        }
    }
    double uniform() { return double(next() >> 11) * 0x1.0p-53; }  // [0, 1)

private:
    static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    std::uint64_t next() {
        const std::uint64_t result = rotl(state_[1] * 5, 7) * 9, t = state_[1] << 17;
        state_[2] ^= state_[0];
        state_[3] ^= state_[1];
        state_[1] ^= state_[2];
        state_[0] ^= state_[3];
        state_[2] ^= t;
        state_[3] = rotl(state_[3], 45);
        return result;
    }
    std::uint64_t state_[4];
};

// Orthonormal basis with `n` as its third axis (Duff et al. 2017).
void basis(const glm::dvec3& n, glm::dvec3& b1, glm::dvec3& b2) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z), b = n.x * n.y * a;
    b1 = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
    b2 = {b, sign + n.y * n.y * a, -n.y};
}

// The normal map's direction (glsl/shade_surface.glsl's normal_mapped(), glTF 2.0 §3.9.3) in the frame of
// the interpolated normal n and the hit's tangent: normalize(T x s + B y s + N z), (x, y, z) = 2 texel - 1,
// B = w cross(N, T) with T made orthogonal to N. n unchanged without a tangent.
glm::dvec3 normal_mapped(const glm::dvec3& n, const glm::dvec4& tangent, const glm::vec3& texel, double scale) {
    glm::dvec3 t = glm::dvec3(tangent) - n * glm::dot(n, glm::dvec3(tangent));
    const double t_length = glm::length(t);
    if (!(t_length > 0.0)) return n;
    t /= t_length;
    const glm::dvec3 b = (tangent.w < 0.0 ? -1.0 : 1.0) * glm::cross(n, t);
    const glm::dvec3 m = (2.0 * glm::dvec3(texel) - 1.0) * glm::dvec3(scale, scale, 1.0);
    const glm::dvec3 mapped = m.x * t + m.y * b + m.z * n;
    const double length = glm::length(mapped);
    return length > 0.0 ? mapped / length : n;
}

// The shading normal (docs/DESIGN.md §5.4), as glsl/shade_surface.glsl's shading_normal(): the normal,
// interpolated and normal-mapped, turned round where the triangle's back is seen; where it still faces away
// from the viewer near a silhouette, bent towards the viewer in the plane of n and v until n.v is about
// kFacingEpsilon; then, for a `mapped` normal, its mirror direction kept above the triangle's plane.
constexpr double kFacingEpsilon = 0.01;  // glsl/shade_surface.glsl's
glm::dvec3 shading_normal(const Hit& hit, const glm::dvec3& normal, bool mapped, const glm::dvec3& view) {
    const bool front = glm::dot(hit.geometric_normal, view) >= 0.0;
    glm::dvec3 n = front ? normal : -normal;
    const double facing = glm::dot(n, view);
    if (facing < kFacingEpsilon) n = glm::normalize(n + (kFacingEpsilon - facing) * view);
    return mapped ? mirror_above_surface(n, front ? hit.geometric_normal : -hit.geometric_normal, view) : n;
}

// What the shading of one surface point needs: the Phong BRDF's k_d, k_s and shininess (docs/DESIGN.md §2),
// or, where the material has them, glTF's metallic-roughness parameters (docs/DESIGN.md §11; k_d and k_s 0).
struct SurfacePoint {
    glm::dvec3 position, normal, geometric_normal, view, mirror;
    glm::dvec3 normal_b1, normal_b2, mirror_b1, mirror_b2;
    glm::dvec3 k_d{0.0};
    double k_s = 0.0, shininess = 1.0;
    std::optional<gltf_brdf::MetallicRoughness> metallic_roughness;  // base_color times the texture's mean
    double alpha = 1.0;                                              // GGX's, from metallic_roughness->roughness
    double offset = 0.0;       // shadow rays start this far off the triangle, on the side they leave towards
    glm::dvec3 emission{0.0};  // Material::emission times its texture's mean: added, lighting nothing
    double occlusion = 1.0;    // the reflected radiance's factor from the occlusion texture (shade.frag's)

    bool has_diffuse() const {
        const glm::dvec3 k =
            metallic_roughness ? (1.0 - metallic_roughness->metallic) * metallic_roughness->base_color : k_d;
        return k.r > 0.0 || k.g > 0.0 || k.b > 0.0;
    }
    // GGX's Fresnel term reflects at grazing angles whatever F0.
    bool has_specular() const { return metallic_roughness || k_s > 0.0; }
};

// Sample counts of the strategies per round: the map's light (EnvironmentSampler), the cosine lobe and
// the specular lobe (Phong's, docs/DESIGN.md §2, or GGX's visible normals, §11): one per term of the BRDF.
struct Allocation {
    int grid = kGrid;  // each strategy in use draws grid x grid jittered samples
    int light = 0, cosine = 0, specular = 0;
    int total() const { return light + cosine + specular; }
    Allocation with_grid(int g) const {
        const auto scale = [&](int count) { return count ? g * g : 0; };
        return {g, scale(light), scale(cosine), scale(specular)};
    }
};

class PixelIntegrator {
public:
    PixelIntegrator(const Scene& scene, const EnvironmentSampler& environment, const RayTracer& tracer)
        : scene_(scene), environment_(environment), tracer_(tracer) {}

    enum class Strategy { light, cosine, specular };

    // One sample's share of the estimate of L = integral of L_env (f_d + f_s) cos theta' V dw over
    // cos theta' > 0: Phong's f_d cos theta' + f_s cos theta' = k_d cos theta' + k_s cos^n psi, or glTF's
    // diffuse and specular lobes (gltf_brdf::evaluate_lobes) times cos theta'. The two terms are estimated
    // apart, each by multiple importance sampling (the power heuristic, Veach 1997, beta = 2) over the
    // strategies that suit it: the diffuse term by the map's light and the cosine lobe, the specular term by
    // the map's light and the specular lobe (Phong's, or GGX's visible normals); a sample adds
    //   f_term w_s / (N_s p_s),  w_s = (N_s p_s)^2 / sum over the term's strategies k of (N_k p_k)^2,
    // and one shadow ray serves both terms.
    glm::dvec3 contribution(const SurfacePoint& s, const Allocation& a, Strategy strategy, const glm::dvec3& w,
                            long long& rays) const {
        const double cos_theta = glm::dot(s.normal, w);
        if (cos_theta <= 0.0) return glm::dvec3(0.0);
        // The ground plane, when the scene has one, hides everything below the horizon (Scene::ground_height).
        if (scene_.has_ground && w.y < 0.0) return glm::dvec3(0.0);
        double light_pdf = 0.0;
        const glm::dvec3 radiance = environment_.radiance_and_pdf(w, light_pdf);
        const double light = a.light * light_pdf;
        const double cosine = a.cosine * cos_theta / kPi;
        // The specular lobe's density, f_d, and f_s cos theta' (without L_env V), by the point's BRDF.
        double specular = 0.0;
        glm::dvec3 diffuse_brdf(0.0), specular_term(0.0);
        if (s.metallic_roughness) {
            specular = a.specular * gltf_brdf::ggx_reflection_pdf(s.normal, s.view, w, s.alpha);
            const gltf_brdf::Lobes lobes = gltf_brdf::evaluate_lobes(*s.metallic_roughness, s.normal, s.view, w);
            diffuse_brdf = lobes.diffuse;
            specular_term = lobes.specular * cos_theta;
        } else {
            const double cos_psi = s.k_s > 0.0 ? glm::dot(s.mirror, w) : 0.0;
            const double lobe = cos_psi > 0.0 ? std::pow(cos_psi, s.shininess) : 0.0;
            specular = a.specular * (s.shininess + 1.0) / (2.0 * kPi) * lobe;
            diffuse_brdf = s.k_d;
            specular_term = glm::dvec3(s.k_s * lobe);
        }
        const double own = strategy == Strategy::light ? light : strategy == Strategy::cosine ? cosine : specular;
        if (!(own > 0.0)) return glm::dvec3(0.0);
        // w_s / (N_s p_s) for each term; a lobe's samples serve only their own term.
        const double diffuse_weight = strategy == Strategy::specular ? 0.0 : own / (light * light + cosine * cosine);
        const double specular_weight = strategy == Strategy::cosine ? 0.0 : own / (light * light + specular * specular);
        const glm::dvec3 weighted =
            radiance * (diffuse_brdf * (cos_theta * diffuse_weight) + specular_term * specular_weight);
        if (weighted.r <= 0.0 && weighted.g <= 0.0 && weighted.b <= 0.0) return glm::dvec3(0.0);
        const double side = glm::dot(s.geometric_normal, w) >= 0.0 ? 1.0 : -1.0;
        ++rays;
        if (tracer_.occluded(s.position + side * s.offset * s.geometric_normal, w, 1e30)) return glm::dvec3(0.0);
        return weighted;
    }

    // The direction a strategy draws from (xi1, xi2) in the unit square.
    glm::dvec3 direction(const SurfacePoint& s, Strategy strategy, double xi1, double xi2) const {
        if (strategy == Strategy::light) return environment_.sample(xi1, xi2).direction;
        if (strategy == Strategy::cosine) {  // cosine-weighted about the normal (Malley)
            const double r = std::sqrt(xi1), phi = 2.0 * kPi * xi2;
            const glm::dvec3 w = r * std::cos(phi) * s.normal_b1 + r * std::sin(phi) * s.normal_b2 +
                                 std::sqrt(std::max(0.0, 1.0 - xi1)) * s.normal;
            return glm::normalize(w);
        }
        if (s.metallic_roughness)  // GGX's visible normals (gltf_brdf::ggx_reflection_pdf)
            return gltf_brdf::sample_ggx_reflection(s.normal, s.view, s.alpha, xi1, xi2).direction;
        // density (n + 1)/(2 pi) cos^n psi about the mirror direction
        const double cos_psi = std::pow(1.0 - xi1, 1.0 / (s.shininess + 1.0));
        const double sin_psi = std::sqrt(std::max(0.0, 1.0 - cos_psi * cos_psi)), phi = 2.0 * kPi * xi2;
        const glm::dvec3 w =
            sin_psi * std::cos(phi) * s.mirror_b1 + sin_psi * std::sin(phi) * s.mirror_b2 + cos_psi * s.mirror;
        return glm::normalize(w);
    }

    // One round at one surface point: an unbiased estimate of its radiance, independent of the other
    // rounds. Each strategy draws from a jittered a.grid x a.grid grid on the unit square.
    glm::dvec3 round(const SurfacePoint& s, const Allocation& a, Random& random, long long& rays) const {
        glm::dvec3 sum(0.0);
        const auto jittered = [&](int k, double& xi1, double& xi2) {
            xi1 = (k % a.grid + random.uniform()) / a.grid;
            xi2 = (k / a.grid + random.uniform()) / a.grid;
        };
        double xi1, xi2;
        for (const auto& [strategy, count] :
             {std::pair{Strategy::light, a.light}, {Strategy::cosine, a.cosine}, {Strategy::specular, a.specular}}) {
            for (int k = 0; k < count; ++k) {
                jittered(k, xi1, xi2);
                sum += contribution(s, a, strategy, direction(s, strategy, xi1, xi2), rays);
            }
        }
        return sum;
    }

private:
    const Scene& scene_;
    const EnvironmentSampler& environment_;
    const RayTracer& tracer_;
};

// Mean and spread of independent round estimates (Welford), per channel.
class RoundStatistics {
public:
    void add(const glm::dvec3& estimate) {
        ++count_;
        const glm::dvec3 delta = estimate - mean_;
        mean_ += delta / double(count_);
        m2_ += delta * (estimate - mean_);
    }
    long long count() const { return count_; }
    const glm::dvec3& mean() const { return mean_; }
    glm::dvec3 variance() const { return count_ > 1 ? m2_ / double(count_ - 1) : glm::dvec3(0.0); }
    glm::dvec3 standard_error() const { return glm::sqrt(variance() / double(count_)); }

private:
    long long count_ = 0;
    glm::dvec3 mean_{0.0}, m2_{0.0};
};

// The texture's mean over a pixel's footprint in uv: the parallelogram about the hit's texture
// coordinates spanned by the steps to the neighbouring pixels' rays (through the hit triangle's plane),
// sampled on a grid of up to kMaxFootprintTaps^2 bilinear taps, about one per texel. Without a
// neighbour (a ray parallel to the plane), the one tap at the hit. `premultiplied`: each tap's colour weighed
// by its alpha (a blended surface's colour where the surface is; shade.frag's premultiplied_footprint).
constexpr int kMaxFootprintTaps = 16;
glm::vec3 footprint_mean(const MaterialTexture& texture, const Hit& hit, const std::optional<glm::dvec2>& right,
                         const std::optional<glm::dvec2>& below, bool premultiplied = false) {
    const glm::dvec2 centre(hit.texcoord);
    if (!right || !below) return sample_linear_rgb(texture, hit.texcoord);
    const glm::dvec2 du = *right - centre, dv = *below - centre;
    const glm::dvec2 size(texture.image->width, texture.image->height);
    const double texels = std::max(glm::length(du * size), glm::length(dv * size));
    if (!std::isfinite(texels)) return sample_linear_rgb(texture, hit.texcoord);
    const int taps = std::clamp(int(std::ceil(texels)), 1, kMaxFootprintTaps);
    glm::dvec3 sum(0.0);
    double weight = 0.0;
    for (int j = 0; j < taps; ++j)
        for (int i = 0; i < taps; ++i) {
            const double a = (i + 0.5) / taps - 0.5, b = (j + 0.5) / taps - 0.5;
            const glm::vec4 texel = sample_linear_rgba(texture, glm::vec2(centre + a * du + b * dv));
            const double w = premultiplied ? double(texel.a) : 1.0;
            sum += w * glm::dvec3(texel);
            weight += w;
        }
    return weight > 0.0 ? glm::vec3(sum / weight) : sample_linear_rgb(texture, hit.texcoord);
}

// A camera ray's hit with gaps narrower than the rasteriser's vertex precision closed (docs/DESIGN.md §5.8):
// rasterisers snap vertices to 1/2^8 of a pixel (GL_SUBPIXEL_BITS on llvmpipe and desktop GPUs), so a
// crack between two surfaces that nearly meet (the separately tessellated faces of a CAD model, microns
// apart) covers no pixel centre there, whereas the exact ray through a centre can slip through it and
// find the inside of a part. Where the rays 1/256 pixel to either side (in x, or in y) both hit nearer
// than the centre's ray, by more than kGapDepthSteps times that step's width, the centre lies in such
// a gap: its hit is taken on the plane of the nearer of the two triangles. `ray(px, py)`: the unit
// direction through a point of the image, in pixels.
constexpr double kSubpixelStep = 1.0 / 256.0;
constexpr double kGapDepthSteps = 10.0;  // deeper than a V-shaped crease of slope 10 between the two rays
// `salt`: RayTracer::intersect's, for blended surfaces.
template <class RayThrough>
std::optional<Hit> camera_hit(const RayTracer& tracer, const glm::dvec3& eye, const RayThrough& ray, double px,
                              double py, std::uint32_t salt = 0) {
    const glm::dvec3 direction = ray(px, py);
    const std::optional<Hit> centre = tracer.intersect(eye, direction, salt);
    const double centre_distance = centre ? centre->distance : std::numeric_limits<double>::infinity();
    std::optional<Hit> cover;
    for (const glm::dvec2 step : {glm::dvec2(kSubpixelStep, 0.0), glm::dvec2(0.0, kSubpixelStep)}) {
        const glm::dvec3 plus = ray(px + step.x, py + step.y), minus = ray(px - step.x, py - step.y);
        const std::optional<Hit> a = tracer.intersect(eye, plus, salt);
        const std::optional<Hit> b = tracer.intersect(eye, minus, salt);
        if (!a || !b) continue;
        const Hit& nearer = a->distance <= b->distance ? *a : *b;
        const double farther = std::max(a->distance, b->distance);
        const double step_width = 0.5 * farther * glm::length(plus - minus);
        if (centre_distance - farther <= kGapDepthSteps * step_width) continue;
        if (!cover || nearer.distance < cover->distance) cover = nearer;
    }
    if (!cover) return centre;
    const std::optional<Hit> on_plane = tracer.hit_on_plane(*cover, eye, direction);
    return on_plane ? on_plane : cover;
}

struct PixelResult {
    glm::dvec3 value{0.0}, standard_error{0.0};
    long long samples = 0;
    double relative_error = 0.0;
    double coverage = 0.0;  // the share of the pixel that objects cover (0 or 1 at a point)
    bool object = false, dark = false;
};

// Camera rays at the centres of a kProbeGrid x kProbeGrid grid over a pixel decide, under the box filter,
// whether any object covers it; a pixel they all miss shows the map, averaged over them.
constexpr int kProbeGrid = 4;

// Each position of a round over a pixel's area takes about one sample of each strategy.
constexpr int kStrategies = 3;

}  // namespace

ReferenceImage render_reference(const Scene& scene, const EnvironmentMap& map, const ReferenceOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    const EnvironmentSampler environment(map, scene.environment.rotation_degrees);
    const RayTracer tracer(scene, options.time);
    const PixelIntegrator integrator(scene, environment, tracer);
    const int width = options.width, height = options.height;
    const bool box = options.pixel_filter == PixelFilter::box;

    // Camera rays through points of the image plane, row 0 at the top, as OpenGL rasterises with Camera's
    // matrices.
    const glm::dmat4 world_from_view = glm::inverse(glm::dmat4(scene.camera.view_from_world()));
    const glm::dmat3 world_from_view_rotation(world_from_view);
    const glm::dvec3 eye(world_from_view[3]);
    const double tan_half_fov = std::tan(0.5 * glm::radians(double(scene.camera.fov_y_degrees)));
    const double aspect = double(width) / double(height);
    // Pixels darker than 2% of the map's mean radiance stop on an absolute error (target * floor) instead.
    const double dark_floor = 0.02 * environment.mean_luminance();

    // The unit world direction through a point (px, py) of the image, in pixels from its top left corner.
    const auto ray = [&](double px, double py) {
        const glm::dvec3 v((2.0 * px / width - 1.0) * tan_half_fov * aspect, (1.0 - 2.0 * py / height) * tan_half_fov,
                           -1.0);
        return glm::normalize(world_from_view_rotation * v);
    };

    // The surface point that the camera ray through (px, py) in `direction` meets at `hit`.
    // `footprint`: the width, in pixels, of the part of the image this ray stands for (a pixel; at a
    // point of a round over the pixel's area, its stratum), over which the base-colour texture is averaged.
    const auto surface_at = [&](const Hit& hit, const glm::dvec3& direction, double px, double py, double footprint) {
        const Material& material = scene.objects[hit.object].material;
        SurfacePoint s;
        s.position = hit.position;
        s.geometric_normal = hit.geometric_normal;
        const glm::dvec3 view = -direction;
        // Textures are averaged over the ray's footprint (as the GPU's mip level does over a pixel;
        // docs/DESIGN.md §5.12).
        const bool textured = !scene.objects[hit.object].mesh->texcoords.empty();
        const auto texture_mean = [&](const MaterialTexture& t, bool premultiplied = false) {
            return footprint_mean(t, hit, tracer.texcoord_on_plane(hit, eye, ray(px + footprint, py)),
                                  tracer.texcoord_on_plane(hit, eye, ray(px, py + footprint)), premultiplied);
        };
        const bool mapped = material.normal_texture && textured && material.normal_scale != 0.0f;
        const glm::dvec3 normal = mapped ? normal_mapped(hit.shading_normal, hit.tangent,
                                                         texture_mean(*material.normal_texture), material.normal_scale)
                                         : hit.shading_normal;
        s.normal = shading_normal(hit, normal, mapped, view);
        s.view = view;
        s.mirror = glm::normalize(2.0 * glm::dot(s.normal, view) * s.normal - view);
        basis(s.normal, s.normal_b1, s.normal_b2);
        basis(s.mirror, s.mirror_b1, s.mirror_b2);
        // The base-colour texture scales rho_d (or glTF's base_color) at the hit, as shade.frag's k_d.
        std::optional<glm::vec3> texture;
        if (material.base_color_texture && textured)
            texture = texture_mean(*material.base_color_texture, material.blended());
        s.emission = glm::dvec3(material.emission);
        if (material.emission_texture && textured && material.emission != glm::vec3(0.0f))
            s.emission *= glm::dvec3(texture_mean(*material.emission_texture));
        if (material.occlusion_texture && textured)
            s.occlusion = 1.0 + material.occlusion_strength * (texture_mean(*material.occlusion_texture).r - 1.0);
        if (const std::optional<MetallicRoughness>& m = material.metallic_roughness) {
            // glTF's BRDF in place of the Phong stand-in (docs/DESIGN.md §11).
            glm::vec3 base_color = m->base_color;
            if (texture) base_color *= *texture;
            float metallic = m->metallic, roughness = m->roughness;  // times the texture's B and G, as shade.frag's
            if (material.metallic_roughness_texture && textured) {
                const glm::vec3 parameters = texture_mean(*material.metallic_roughness_texture);
                metallic *= parameters.b;
                roughness *= parameters.g;
            }
            s.metallic_roughness =
                gltf_brdf::MetallicRoughness{glm::dvec3(base_color), double(metallic), double(roughness)};
            s.alpha = gltf_brdf::alpha_from_roughness(roughness);
        } else {
            glm::vec3 rho_d = material.rho_d;
            if (texture) rho_d *= *texture;
            s.k_d = glm::dvec3(brdf::diffuse_coefficient(rho_d.r), brdf::diffuse_coefficient(rho_d.g),
                               brdf::diffuse_coefficient(rho_d.b));
            s.shininess = std::max(0.0, double(material.shininess));
            s.k_s = material.rho_s > 0.0f ? brdf::specular_coefficient(material.rho_s, material.shininess) : 0.0;
        }
        s.offset = 1e-5 * (tracer.extent() + glm::length(s.position));
        return s;
    };
    // The strategies in use at a surface point, grid x grid samples each.
    const auto allocation_at = [&](const SurfacePoint& s, int grid) {
        Allocation a;
        a.grid = grid;
        a.light = environment.can_sample() ? grid * grid : 0;
        a.cosine = s.has_diffuse() ? grid * grid : 0;
        a.specular = s.has_specular() ? grid * grid : 0;
        return a;
    };

    std::vector<PixelResult> pixels(std::size_t(width) * std::size_t(height));
    std::vector<long long> rays_per_row(std::size_t(height), 0);
    std::atomic<int> rows_done{0};
    const auto stopping = [&] { return options.stop && options.stop->load(std::memory_order_relaxed); };
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
        std::vector<int> strata[kStrategies];  // a round's pairing of direction strata with positions
        for (int y = rows.begin(); y < rows.end(); ++y) {
            if (stopping()) return;  // the rows left stay black; the result is thrown away below
            long long rays = 0;
            for (int x = 0; x < width; ++x) {
                PixelResult& out = pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)];
                Random random(options.seed * 0x9e3779b97f4a7c15ull + std::uint64_t(y) * std::uint64_t(width) +
                              std::uint64_t(x));
                // round(grid, samples): one independent, unbiased estimate of the pixel's value, adding the
                // samples it took; per_round(grid): about how many samples a round takes.
                std::function<glm::dvec3(int, long long&)> round;
                std::function<long long(int)> per_round;
                SurfacePoint s;                        // at the pixel's centre (point filter)
                long long positions = 0, covered = 0;  // of the rounds over the pixel's area (box filter)

                if (!box && tracer.has_blended()) {
                    // The centre's ray stops at a blended surface with probability alpha: a fresh draw per
                    // round, each shading what it stops at (over the rounds, alpha of the surface and 1 - alpha
                    // of what is behind).
                    out.object = true;
                    out.coverage = 1.0;
                    round = [&, draw = std::uint32_t(0)](int grid, long long& samples) mutable {
                        const glm::dvec3 direction = ray(x + 0.5, y + 0.5);
                        const std::optional<Hit> hit = camera_hit(tracer, eye, ray, x + 0.5, y + 0.5, ++draw);
                        ++samples;
                        if (!hit) return environment.radiance_filtered(direction);
                        const SurfacePoint p = surface_at(*hit, direction, x + 0.5, y + 0.5, 1.0);
                        const Allocation a = allocation_at(p, grid);
                        if (environment.luminance_integral() <= 0.0 || a.cosine + a.specular == 0) return p.emission;
                        samples += a.total();
                        return p.emission + p.occlusion * integrator.round(p, a, random, rays);
                    };
                    per_round = [](int grid) { return (long long)kStrategies * grid * grid; };
                } else if (!box) {
                    const glm::dvec3 direction = ray(x + 0.5, y + 0.5);
                    const std::optional<Hit> hit = camera_hit(tracer, eye, ray, x + 0.5, y + 0.5);
                    if (!hit) {
                        out.value = environment.radiance_filtered(direction);
                        continue;
                    }
                    out.object = true;
                    out.coverage = 1.0;
                    s = surface_at(*hit, direction, x + 0.5, y + 0.5, 1.0);
                    const Allocation allocation = allocation_at(s, kGrid);
                    if (environment.luminance_integral() <= 0.0 || allocation.cosine + allocation.specular == 0) {
                        out.value = s.emission;  // a black map or a black material: the emission exactly
                        out.dark = true;
                        continue;
                    }
                    round = [&, allocation](int grid, long long& samples) {
                        const Allocation a = allocation.with_grid(grid);
                        samples += a.total();
                        return s.emission + s.occlusion * integrator.round(s, a, random, rays);
                    };
                    per_round = [allocation](int grid) { return (long long)allocation.with_grid(grid).total(); };
                } else {
                    // Under the box filter the value is the mean over the pixel's square, as the renderer's
                    // multisample resolve averages its samples with equal weights.
                    bool any = false;
                    glm::dvec3 map_sum(0.0);
                    for (int k = 0; k < kProbeGrid * kProbeGrid; ++k) {
                        const glm::dvec3 direction =
                            ray(x + (k % kProbeGrid + 0.5) / kProbeGrid, y + (k / kProbeGrid + 0.5) / kProbeGrid);
                        if (tracer.intersect(eye, direction, 0, /*blended_always_hit=*/true)) {
                            any = true;
                            break;
                        }
                        map_sum += environment.radiance_filtered(direction);
                    }
                    if (!any) {
                        out.value = map_sum / double(kProbeGrid * kProbeGrid);
                        continue;
                    }
                    out.object = true;
                    // A round: grid x grid positions jittered in the pixel's strata; at each, the first hit
                    // of the camera ray takes one sample of each of its strategies (the map shows where the
                    // ray hits nothing). Each strategy's direction strata are shuffled against the positions
                    // every round, so that any pairing is as likely (no bias) and both stay stratified.
                    // Camera rays are not closed over cracks here (camera_hit): a crack narrower than the
                    // rasteriser resolves covers that share of the pixel, and a share of samples as small.
                    round = [&](int grid, long long& samples) {
                        const int n = grid * grid;
                        for (std::vector<int>& order : strata) {
                            if (int(order.size()) != n) {
                                order.resize(std::size_t(n));
                                for (int k = 0; k < n; ++k) order[std::size_t(k)] = k;
                            }
                            for (int k = n - 1; k > 0; --k)
                                std::swap(order[std::size_t(k)],
                                          order[std::size_t(std::min(k, int(random.uniform() * (k + 1))))]);
                        }
                        glm::dvec3 sum(0.0);
                        for (int k = 0; k < n; ++k) {
                            const double px = x + (k % grid + random.uniform()) / grid;
                            const double py = y + (k / grid + random.uniform()) / grid;
                            const glm::dvec3 direction = ray(px, py);
                            ++positions;
                            const std::optional<Hit> hit = tracer.intersect(eye, direction);
                            if (!hit) {
                                sum += environment.radiance_filtered(direction) / double(n);
                                ++samples;
                                continue;
                            }
                            ++covered;
                            const SurfacePoint p = surface_at(*hit, direction, px, py, 1.0 / grid);
                            sum += p.emission / double(n);
                            const Allocation a = allocation_at(p, grid);
                            if (a.cosine + a.specular == 0) continue;  // a black material: reflects nothing
                            const std::pair<PixelIntegrator::Strategy, int> in_use[] = {
                                {PixelIntegrator::Strategy::light, a.light},
                                {PixelIntegrator::Strategy::cosine, a.cosine},
                                {PixelIntegrator::Strategy::specular, a.specular}};
                            for (int i = 0; i < kStrategies; ++i) {
                                if (in_use[i].second == 0) continue;
                                const int stratum = strata[i][std::size_t(k)];
                                const double xi1 = (stratum % grid + random.uniform()) / grid;
                                const double xi2 = (stratum / grid + random.uniform()) / grid;
                                sum += p.occlusion * integrator.contribution(
                                                         p, a, in_use[i].first,
                                                         integrator.direction(p, in_use[i].first, xi1, xi2), rays);
                                ++samples;
                            }
                        }
                        return sum;
                    };
                    per_round = [](int grid) { return (long long)kStrategies * grid * grid; };
                }

                // A pilot plans the rounds; fresh rounds, independent of that decision, give the value and
                // its error (stopping on the rounds that are reported would favour runs whose spread happened
                // to look small). A pixel that needs many rounds takes larger ones (grid 12 or 24): a finer
                // stratification cuts the variance per sample where edges and shadows make it high; a second
                // pilot at that size plans them.
                const double target = options.target_error;
                long long samples = 0;
                const auto run = [&](int grid, long long count, RoundStatistics& into) {
                    long long taken = 0;
                    for (long long k = 0; k < count; ++k) into.add(round(grid, taken));
                    samples += taken;
                    return taken;
                };
                // Rounds for every channel's standard error to reach target * max(value, dark floor).
                const auto rounds_for = [&](const RoundStatistics& r, int grid) {
                    const long long cap = std::max<long long>(kMinRounds, options.max_samples / per_round(grid));
                    const glm::dvec3 goal = target * glm::max(r.mean(), glm::dvec3(dark_floor));
                    const glm::dvec3 rounds = kPlanMargin * r.variance() / (goal * goal);
                    const double most = std::max({rounds.r, rounds.g, rounds.b});
                    return most < double(cap) ? std::max<long long>(kMinRounds, (long long)std::ceil(most)) : cap;
                };
                RoundStatistics pilot;
                run(kGrid, kPilotRounds, pilot);
                long long planned = rounds_for(pilot, kGrid);
                // At least as good as independent samples, a round g times finer needs at most 1/g^2 the rounds.
                int grid = kGrid;
                while (grid < kLargestGrid &&
                       double(planned) * double(kGrid * kGrid) / double(4 * grid * grid) >= kMinRounds)
                    grid *= 2;
                if (grid != kGrid) {
                    RoundStatistics second_pilot;
                    run(grid, kPilotRounds, second_pilot);
                    planned = rounds_for(second_pilot, grid);
                }
                RoundStatistics rounds;
                long long fresh_samples = run(grid, planned, rounds);
                // The pilot misjudged (its variance is a 7-degree-of-freedom estimate): one top-up.
                fresh_samples += run(grid, std::max<long long>(0, rounds_for(rounds, grid) - rounds.count()), rounds);

                out.value = rounds.mean();
                if (box) out.coverage = double(covered) / double(positions);
                // The rounds' spread cannot show what no sample met (a small occluder all samples passed by):
                // add value / N, about the weight of a feature N samples are likely to miss (rule of three).
                const glm::dvec3 resolution = out.value / double(std::max<long long>(1, fresh_samples));
                out.standard_error =
                    glm::sqrt(rounds.standard_error() * rounds.standard_error() + resolution * resolution);
                out.samples = samples;
                out.dark = true;  // unless some channel is above the floor: then its relative error counts
                for (int c = 0; c < 3; ++c) {
                    if (out.value[c] < dark_floor) continue;
                    out.dark = false;
                    out.relative_error = std::max(out.relative_error, out.standard_error[c] / out.value[c]);
                }
            }
            rays_per_row[std::size_t(y)] = rays;
            const int done = rows_done.fetch_add(1, std::memory_order_relaxed) + 1;
            if (options.on_row_done) options.on_row_done(done, height);
        }
    });
    if (rows_done.load() < height) throw Interrupted("interrupted");

    ReferenceImage result;
    result.image = Image(width, height);
    result.standard_error = Image(width, height);
    ReferenceStatistics& stats = result.statistics;
    std::vector<double> relative_errors;
    double samples = 0.0;
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const PixelResult& p = pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)];
            result.image.at(x, y) = glm::vec4(glm::vec3(p.value), float(p.coverage));
            result.standard_error.at(x, y) = glm::vec4(glm::vec3(p.standard_error), float(p.samples));
            if (!p.object) continue;
            ++stats.object_pixels;
            samples += double(p.samples);
            if (p.dark) {
                ++stats.dark_pixels;
                continue;
            }
            relative_errors.push_back(p.relative_error);
            if (p.relative_error > 0.005) ++stats.pixels_over_half_percent;
        }
    }
    for (long long rays : rays_per_row) stats.shadow_rays += rays;
    if (stats.object_pixels > 0) stats.mean_samples = samples / double(stats.object_pixels);
    if (!relative_errors.empty()) {
        double sum = 0.0;
        for (double e : relative_errors) sum += e;
        stats.mean_relative_error = sum / double(relative_errors.size());
        std::sort(relative_errors.begin(), relative_errors.end());
        stats.p99_relative_error =
            relative_errors[std::min(relative_errors.size() - 1, std::size_t(0.99 * double(relative_errors.size())))];
        stats.max_relative_error = relative_errors.back();
    }
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace envshadow::reference
