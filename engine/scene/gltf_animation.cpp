#include "scene/gltf_animation.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_inverse.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat3x3.hpp>

#include "core/log.h"
#include "scene/gltf_accessor.h"
#include "scene/meshes.h"

namespace envshadow {
namespace {

// Hermite basis of glTF 2.0 Appendix C: p(s) = h00 v_k + h10 td b_k + h01 v_k+1 + h11 td a_k+1.
struct Hermite {
    float h00, h10, h01, h11;
    explicit Hermite(float s) {
        const float s2 = s * s, s3 = s2 * s;
        h00 = 2.0f * s3 - 3.0f * s2 + 1.0f;
        h10 = s3 - 2.0f * s2 + s;
        h01 = -2.0f * s3 + 3.0f * s2;
        h11 = s3 - s2;
    }
};

glm::mat4 local_matrix(const GltfNode& node) {
    if (node.has_matrix) return node.matrix;
    return glm::translate(glm::mat4(1.0f), node.translation) * glm::mat4_cast(node.rotation) *
           glm::scale(glm::mat4(1.0f), node.scale);
}

}  // namespace

void GltfSampler::sample(double t, bool rotation, float* out) const {
    const std::size_t keys = input.size();
    const std::size_t n = std::size_t(components);
    const bool cubic = interpolation == GltfInterpolation::cubic_spline;
    // Element `k`'s value (cubic splines: the middle of in-tangent, value, out-tangent).
    auto value = [&](std::size_t k) { return output.data() + (cubic ? (3 * k + 1) * n : k * n); };
    auto copy = [&](const float* v) { std::copy(v, v + n, out); };
    if (keys == 0) return;
    if (keys == 1 || t <= double(input.front())) return copy(value(0));
    if (t >= double(input.back())) return copy(value(keys - 1));
    const std::size_t k = std::size_t(std::upper_bound(input.begin(), input.end(), float(t)) - input.begin()) - 1;
    const float t0 = input[k], t1 = input[k + 1];
    const float td = t1 - t0;
    const float s = std::clamp(float((t - double(t0)) / double(td)), 0.0f, 1.0f);
    switch (interpolation) {
        case GltfInterpolation::step:
            return copy(value(k));
        case GltfInterpolation::linear: {
            const float* a = value(k);
            const float* b = value(k + 1);
            if (rotation) {  // shortest-path slerp of unit quaternions (x, y, z, w in the file)
                const glm::quat qa(a[3], a[0], a[1], a[2]), qb(b[3], b[0], b[1], b[2]);
                const glm::quat q = glm::normalize(glm::slerp(glm::normalize(qa), glm::normalize(qb), s));
                out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
                return;
            }
            for (std::size_t c = 0; c < n; ++c) out[c] = a[c] + s * (b[c] - a[c]);
            return;
        }
        case GltfInterpolation::cubic_spline: {
            const Hermite h(s);
            const float* v0 = value(k);
            const float* b0 = v0 + n;  // out-tangent of key k
            const float* v1 = value(k + 1);
            const float* a1 = v1 - n;  // in-tangent of key k + 1
            for (std::size_t c = 0; c < n; ++c)
                out[c] = h.h00 * v0[c] + h.h10 * td * b0[c] + h.h01 * v1[c] + h.h11 * td * a1[c];
            if (rotation) {
                const glm::quat q = glm::normalize(glm::quat(out[3], out[0], out[1], out[2]));
                out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
            }
            return;
        }
    }
}

void GltfRig::pose(int clip, double t, std::vector<glm::mat4>& world, std::vector<std::vector<float>>& weights) const {
    std::vector<GltfNode> posed = nodes;
    if (clip >= 0 && std::size_t(clip) < clips.size()) {
        const GltfClip& c = clips[std::size_t(clip)];
        float value[4];
        for (const GltfChannel& channel : c.channels) {
            const GltfSampler& sampler = c.samplers[std::size_t(channel.sampler)];
            GltfNode& node = posed[std::size_t(channel.node)];
            switch (channel.path) {
                case GltfChannel::Path::translation:
                    sampler.sample(t, false, value);
                    node.translation = glm::vec3(value[0], value[1], value[2]);
                    break;
                case GltfChannel::Path::rotation:
                    sampler.sample(t, true, value);
                    node.rotation = glm::normalize(glm::quat(value[3], value[0], value[1], value[2]));
                    break;
                case GltfChannel::Path::scale:
                    sampler.sample(t, false, value);
                    node.scale = glm::vec3(value[0], value[1], value[2]);
                    break;
                case GltfChannel::Path::weights:
                    node.weights.resize(std::size_t(sampler.components));
                    sampler.sample(t, false, node.weights.data());
                    break;
            }
        }
    }
    world.assign(nodes.size(), glm::mat4(1.0f));
    weights.resize(nodes.size());
    for (const int i : order) {
        const GltfNode& node = posed[std::size_t(i)];
        const glm::mat4 local = local_matrix(node);
        world[std::size_t(i)] = node.parent >= 0 ? world[std::size_t(node.parent)] * local : local;
        weights[std::size_t(i)] = node.weights;
    }
}

namespace {

void pose_vertices(const GltfRig& rig, const GltfPartSources& sources, int clip, double t, Mesh& mesh) {
    std::vector<glm::mat4> world;
    std::vector<std::vector<float>> weights;
    rig.pose(clip, t, world, weights);
    // Joint matrices per skin: G(joint) IBM (the skinned node's own transform is not used, §3.7.3.1).
    std::vector<std::vector<glm::mat4>> joint_matrices(rig.skins.size());
    for (std::size_t s = 0; s < rig.skins.size(); ++s)
        for (std::size_t j = 0; j < rig.skins[s].joints.size(); ++j)
            joint_matrices[s].push_back(world[std::size_t(rig.skins[s].joints[j])] * rig.skins[s].inverse_bind[j]);
    mesh.positions.resize(sources.vertices.size());
    mesh.normals.resize(sources.vertices.size());
    for (std::size_t v = 0; v < sources.vertices.size(); ++v) {
        const GltfVertexSource& src = sources.vertices[v];
        glm::vec3 p = src.position, n = src.normal;
        const std::vector<float>& m = weights[src.node];
        for (std::uint32_t k = 0; k < src.morph_count && k < m.size(); ++k) {
            p += m[k] * sources.morph_deltas[src.morph_first + 2 * k];
            n += m[k] * sources.morph_deltas[src.morph_first + 2 * k + 1];
        }
        glm::mat4 matrix;
        if (src.skin >= 0) {
            const std::vector<glm::mat4>& joints = joint_matrices[std::size_t(src.skin)];
            matrix = glm::mat4(0.0f);
            for (int j = 0; j < 4; ++j)
                if (src.weights[j] != 0.0f) matrix += src.weights[j] * joints[src.joints[j]];
        } else {
            matrix = world[src.node];
        }
        mesh.positions[v] = glm::vec3(matrix * glm::vec4(p, 1.0f));
        glm::vec3 normal = glm::inverseTranspose(glm::mat3(matrix)) * n;
        const float length = glm::length(normal);
        mesh.normals[v] = length > 1e-20f && std::isfinite(length) ? normal / length : src.normal;
        if (mesh.tangents.size() == sources.vertices.size()) {  // a tangent that collapses keeps the last pose's
            const glm::vec4 tangent =
                transform_tangent(glm::dmat3(glm::mat3(matrix)), src.tangent, glm::dvec3(mesh.normals[v]));
            if (glm::vec3(tangent) != glm::vec3(0.0f)) mesh.tangents[v] = tangent;
        }
        if (!std::isfinite(mesh.positions[v].x + mesh.positions[v].y + mesh.positions[v].z))
            mesh.positions[v] = glm::vec3(0.0f);  // a degenerate pose: the vertex collapses, nothing overflows
    }
    mesh.compute_bounds();
}

}  // namespace

void pose_rest(const GltfRig& rig, const GltfPartSources& sources, Mesh& mesh) {
    pose_vertices(rig, sources, -1, 0.0, mesh);
}

MeshDeformation::MeshDeformation(std::shared_ptr<const GltfRig> rig, std::shared_ptr<const GltfPartSources> sources,
                                 std::shared_ptr<const Mesh> bind, int clip, bool loop)
    : rig_(std::move(rig)), sources_(std::move(sources)), bind_(std::move(bind)), clip_(clip), loop_(loop) {
    rigid_ = !sources_->skinned && !sources_->morphed && sources_->one_node && !sources_->vertices.empty();
    if (rigid_) {
        std::vector<glm::mat4> world;
        std::vector<std::vector<float>> weights;
        rig_->pose(-1, 0.0, world, weights);
        rest_inverse_ = glm::inverse(world[sources_->vertices.front().node]);
    }
    cached_time_ = std::numeric_limits<double>::quiet_NaN();
}

double MeshDeformation::duration() const {
    return clip_ >= 0 && std::size_t(clip_) < rig_->clips.size() ? rig_->clips[std::size_t(clip_)].duration : 0.0;
}

double MeshDeformation::clip_time(double t) const {
    const double d = duration();
    if (!(d > 0.0)) return 0.0;
    if (!loop_) return std::clamp(t, 0.0, d);
    const double f = t / d - std::floor(t / d);
    return f < 1.0 ? f * d : 0.0;
}

glm::mat4 MeshDeformation::rigid_motion(double t) const {
    if (!rigid_) return glm::mat4(1.0f);
    std::vector<glm::mat4> world;
    std::vector<std::vector<float>> weights;
    rig_->pose(clip_, clip_time(t), world, weights);
    return world[sources_->vertices.front().node] * rest_inverse_;
}

void MeshDeformation::pose_into(double clip_t, Mesh& mesh) const {
    pose_vertices(*rig_, *sources_, clip_, clip_t, mesh);
}

std::shared_ptr<const Mesh> MeshDeformation::mesh_at(double t) const {
    if (rigid_) return bind_;
    const double ct = clip_time(t);
    std::lock_guard<std::mutex> lock(mutex_);
    if (ct == cached_time_ && cached_) return cached_;
    // Indices and texture coordinates are the bind mesh's: copied once, then only the vertices are
    // rewritten (in place while nobody else holds the last pose; a new copy otherwise).
    if (!cached_ || cached_.use_count() > 1) cached_ = std::make_shared<Mesh>(*bind_);
    pose_into(ct, *cached_);
    cached_time_ = ct;
    return cached_;
}

// ---- reading -----------------------------------------------------------------------------------

GltfRig read_gltf_rig(const GltfAccessors& accessors, const tinygltf::Model& model) {
    GltfRig rig;
    rig.nodes.resize(model.nodes.size());
    for (std::size_t i = 0; i < model.nodes.size(); ++i) {
        const tinygltf::Node& in = model.nodes[i];
        GltfNode& node = rig.nodes[i];
        if (in.matrix.size() == 16) {
            node.has_matrix = true;
            node.matrix = glm::mat4(glm::make_mat4(in.matrix.data()));
        }
        if (in.translation.size() == 3)
            node.translation = glm::vec3(float(in.translation[0]), float(in.translation[1]), float(in.translation[2]));
        if (in.rotation.size() == 4)
            node.rotation = glm::normalize(
                glm::quat(float(in.rotation[3]), float(in.rotation[0]), float(in.rotation[1]), float(in.rotation[2])));
        if (in.scale.size() == 3) node.scale = glm::vec3(float(in.scale[0]), float(in.scale[1]), float(in.scale[2]));
        const std::vector<double>* w = &in.weights;
        if (w->empty() && in.mesh >= 0 && std::size_t(in.mesh) < model.meshes.size())
            w = &model.meshes[std::size_t(in.mesh)].weights;
        for (const double x : *w) node.weights.push_back(float(x));
        if (in.mesh >= 0 && std::size_t(in.mesh) < model.meshes.size()) {
            std::size_t targets = 0;
            for (const auto& prim : model.meshes[std::size_t(in.mesh)].primitives)
                targets = std::max(targets, prim.targets.size());
            node.weights.resize(targets, 0.0f);
        }
        for (const int child : in.children)
            if (child >= 0 && std::size_t(child) < rig.nodes.size()) rig.nodes[std::size_t(child)].parent = int(i);
    }
    // Parents before children (the node graph is a forest: scene/gltf.cpp checked the scene's part).
    std::vector<bool> placed(rig.nodes.size(), false);
    for (std::size_t i = 0; i < rig.nodes.size(); ++i) {
        if (rig.nodes[i].parent >= 0) continue;
        std::vector<int> stack{int(i)};
        while (!stack.empty()) {
            const int n = stack.back();
            stack.pop_back();
            if (placed[std::size_t(n)]) continue;
            placed[std::size_t(n)] = true;
            rig.order.push_back(n);
            for (const int child : model.nodes[std::size_t(n)].children)
                if (child >= 0 && std::size_t(child) < rig.nodes.size() && rig.nodes[std::size_t(child)].parent == n)
                    stack.push_back(child);
        }
    }

    for (std::size_t s = 0; s < model.skins.size(); ++s) {
        const tinygltf::Skin& in = model.skins[s];
        const std::string what = "skin " + std::to_string(s);
        GltfSkin skin;
        if (in.joints.empty()) accessors.fail(what + " has no joints");
        for (const int joint : in.joints) {
            if (joint < 0 || std::size_t(joint) >= rig.nodes.size())
                accessors.fail(what + " joint " + std::to_string(joint) + " is not a node");
            skin.joints.push_back(joint);
        }
        if (in.inverseBindMatrices >= 0) {
            const std::vector<float> m =
                accessors.floats(in.inverseBindMatrices, {.type = TINYGLTF_TYPE_MAT4}, what + " inverseBindMatrices");
            if (m.size() / 16 < skin.joints.size())
                accessors.fail(what + " has " + std::to_string(m.size() / 16) + " inverseBindMatrices for " +
                               std::to_string(skin.joints.size()) + " joints");
            for (std::size_t k = 0; k < 16 * skin.joints.size(); ++k)
                if (!std::isfinite(m[k]) || std::abs(m[k]) > 1e12f)
                    accessors.fail(what + " inverseBindMatrices value " + std::to_string(k) +
                                   " is not finite or beyond 1e12");
            for (std::size_t j = 0; j < skin.joints.size(); ++j)
                skin.inverse_bind.push_back(glm::make_mat4(&m[16 * j]));
        } else {
            skin.inverse_bind.assign(skin.joints.size(), glm::mat4(1.0f));
        }
        rig.skins.push_back(std::move(skin));
    }

    for (std::size_t a = 0; a < model.animations.size(); ++a) {
        const tinygltf::Animation& in = model.animations[a];
        const std::string what = "animation " + std::to_string(a);
        GltfClip clip;
        clip.name = in.name;
        std::vector<int> used(in.samplers.size(), -1);  // components asked of each sampler
        for (std::size_t c = 0; c < in.channels.size(); ++c) {
            const tinygltf::AnimationChannel& ch = in.channels[c];
            const std::string cwhat = what + " channel " + std::to_string(c);
            if (ch.target_node < 0) continue;  // no node: for extensions, ignored (glTF 2.0 §5.6)
            if (std::size_t(ch.target_node) >= rig.nodes.size())
                accessors.fail(cwhat + " targets node " + std::to_string(ch.target_node) + ", which does not exist");
            if (ch.sampler < 0 || std::size_t(ch.sampler) >= in.samplers.size())
                accessors.fail(cwhat + " uses sampler " + std::to_string(ch.sampler) + ", which does not exist");
            GltfChannel channel;
            channel.node = ch.target_node;
            channel.sampler = ch.sampler;
            int components = 3;
            if (ch.target_path == "translation") {
                channel.path = GltfChannel::Path::translation;
            } else if (ch.target_path == "rotation") {
                channel.path = GltfChannel::Path::rotation;
                components = 4;
            } else if (ch.target_path == "scale") {
                channel.path = GltfChannel::Path::scale;
            } else if (ch.target_path == "weights") {
                channel.path = GltfChannel::Path::weights;
                components = int(rig.nodes[std::size_t(ch.target_node)].weights.size());
                if (components == 0) {
                    log::warn(accessors.file().string() + ": " + cwhat + " animates the weights of node " +
                              std::to_string(ch.target_node) + ", which has no morph targets: ignored");
                    continue;
                }
            } else {
                log::warn(accessors.file().string() + ": " + cwhat + " has target path \"" + ch.target_path +
                          "\", which is not supported: ignored");
                continue;
            }
            if (rig.nodes[std::size_t(ch.target_node)].has_matrix && channel.path != GltfChannel::Path::weights)
                accessors.fail(cwhat + " animates node " + std::to_string(ch.target_node) +
                               ", which has a matrix (glTF allows TRS only)");
            int& u = used[std::size_t(ch.sampler)];
            if (u >= 0 && u != components)
                accessors.fail(cwhat + ": sampler " + std::to_string(ch.sampler) +
                               " is shared by paths of different sizes");
            u = components;
            clip.channels.push_back(channel);
        }
        clip.samplers.resize(in.samplers.size());
        for (std::size_t s = 0; s < in.samplers.size(); ++s) {
            if (used[s] < 0) continue;  // no channel reads it
            const tinygltf::AnimationSampler& smp = in.samplers[s];
            const std::string swhat = what + " sampler " + std::to_string(s);
            GltfSampler& sampler = clip.samplers[s];
            if (smp.interpolation == "STEP")
                sampler.interpolation = GltfInterpolation::step;
            else if (smp.interpolation == "LINEAR" || smp.interpolation.empty())
                sampler.interpolation = GltfInterpolation::linear;
            else if (smp.interpolation == "CUBICSPLINE")
                sampler.interpolation = GltfInterpolation::cubic_spline;
            else
                accessors.fail(swhat + " has interpolation \"" + smp.interpolation +
                               "\" (expected STEP, LINEAR or CUBICSPLINE)");
            sampler.components = used[s];
            sampler.input = accessors.floats(smp.input, {.type = TINYGLTF_TYPE_SCALAR}, swhat + " input");
            if (sampler.input.empty()) accessors.fail(swhat + " input has no keys");
            if (!std::isfinite(sampler.input.front()) || !std::isfinite(sampler.input.back()))
                accessors.fail(swhat + " input has a time that is not finite");
            for (std::size_t k = 1; k < sampler.input.size(); ++k)
                if (!(sampler.input[k] > sampler.input[k - 1]))
                    accessors.fail(swhat + " input is not increasing (key " + std::to_string(k) + ": " +
                                   std::to_string(sampler.input[k]) + " after " + std::to_string(sampler.input[k - 1]) +
                                   ")");
            if (sampler.input.front() < 0.0f) accessors.fail(swhat + " input starts before time 0");
            const bool rotation = sampler.components == 4;
            const bool weights = !rotation && [&] {
                for (const GltfChannel& c : clip.channels)
                    if (c.sampler == int(s)) return c.path == GltfChannel::Path::weights;
                return false;
            }();
            AccessorSpec spec{.type = weights    ? TINYGLTF_TYPE_SCALAR
                                      : rotation ? TINYGLTF_TYPE_VEC4
                                                 : TINYGLTF_TYPE_VEC3};
            if (rotation || weights) spec.normalized = spec.signed_normalized = true;
            sampler.output = accessors.floats(smp.output, spec, swhat + " output");
            for (std::size_t k = 0; k < sampler.output.size(); ++k)
                if (!std::isfinite(sampler.output[k]) || std::abs(sampler.output[k]) > 1e12f)
                    accessors.fail(swhat + " output value " + std::to_string(k) + " is not finite or beyond 1e12");
            const std::size_t per_key =
                std::size_t(sampler.components) * (sampler.interpolation == GltfInterpolation::cubic_spline ? 3 : 1);
            if (sampler.output.size() != sampler.input.size() * per_key)
                accessors.fail(swhat + " output has " + std::to_string(sampler.output.size()) + " values for " +
                               std::to_string(sampler.input.size()) + " input keys (expected " +
                               std::to_string(sampler.input.size() * per_key) + ")");
            clip.duration = std::max(clip.duration, double(sampler.input.back()));
        }
        rig.clips.push_back(std::move(clip));
    }
    return rig;
}

GltfPartSources read_primitive_sources(const GltfAccessors& accessors, const tinygltf::Model& model, const GltfRig& rig,
                                       int node, int mesh, int primitive, const std::vector<std::uint32_t>& kept,
                                       std::vector<glm::vec3> positions, std::vector<glm::vec3> normals) {
    const tinygltf::Primitive& prim = model.meshes[std::size_t(mesh)].primitives[std::size_t(primitive)];
    const std::string what = "mesh " + std::to_string(mesh) + " primitive " + std::to_string(primitive);
    const std::size_t vertex_count = accessors.count(prim.attributes.at("POSITION"), what + " POSITION");
    GltfPartSources out;
    out.vertices.resize(kept.size());
    for (std::size_t v = 0; v < kept.size(); ++v) {
        out.vertices[v].position = positions[v];
        out.vertices[v].normal = normals[v];
        out.vertices[v].node = std::uint32_t(node);
    }
    const int skin = model.nodes[std::size_t(node)].skin;
    const auto joints_it = prim.attributes.find("JOINTS_0");
    const auto weights_it = prim.attributes.find("WEIGHTS_0");
    if (skin >= 0 && (joints_it == prim.attributes.end() || weights_it == prim.attributes.end()))
        log::warn(accessors.file().string() + ": " + what +
                  " is on a skinned node but has no JOINTS_0/WEIGHTS_0: not skinned");
    if (skin >= 0 && joints_it != prim.attributes.end() && weights_it != prim.attributes.end()) {
        if (std::size_t(skin) >= rig.skins.size())
            accessors.fail("node " + std::to_string(node) + " refers to skin " + std::to_string(skin) +
                           ", which does not exist");
        const std::size_t joint_count = rig.skins[std::size_t(skin)].joints.size();
        const std::vector<std::uint32_t> joints =
            accessors.uints(joints_it->second, {.type = TINYGLTF_TYPE_VEC4, .floats = false, .unsigned_ints = true},
                            what + " JOINTS_0");
        const std::vector<float> weights =
            accessors.floats(weights_it->second, {.type = TINYGLTF_TYPE_VEC4, .normalized = true}, what + " WEIGHTS_0");
        if (joints.size() / 4 != vertex_count || weights.size() / 4 != vertex_count)
            accessors.fail(what + " has " + std::to_string(joints.size() / 4) + " JOINTS_0 and " +
                           std::to_string(weights.size() / 4) + " WEIGHTS_0 for " + std::to_string(vertex_count) +
                           " positions");
        out.skinned = true;
        for (std::size_t v = 0; v < kept.size(); ++v) {
            GltfVertexSource& src = out.vertices[v];
            src.skin = skin;
            const std::size_t e = kept[v];
            float sum = 0.0f;
            for (int j = 0; j < 4; ++j) {
                const float w = weights[4 * e + std::size_t(j)];
                if (!(w >= 0.0f && w <= 1.0f))
                    accessors.fail(what + " WEIGHTS_0 of vertex " + std::to_string(e) + " is " + std::to_string(w) +
                                   " (weights are numbers in 0 … 1)");
                src.weights[j] = w;
                src.joints[j] = joints[4 * e + std::size_t(j)];
                if (w != 0.0f && src.joints[j] >= joint_count)
                    accessors.fail(what + " JOINTS_0 of vertex " + std::to_string(e) + " is joint " +
                                   std::to_string(src.joints[j]) + ", past skin " + std::to_string(skin) + "'s " +
                                   std::to_string(joint_count) + " joints");
                if (src.joints[j] >= joint_count) src.joints[j] = 0;  // weight 0: unused
                sum += w;
            }
            if (!(sum > 0.0f)) accessors.fail(what + " WEIGHTS_0 of vertex " + std::to_string(e) + " are all 0");
            src.weights /= sum;
        }
    }
    if (!prim.targets.empty()) {
        out.morphed = true;
        const std::size_t targets = prim.targets.size();
        out.morph_deltas.assign(kept.size() * 2 * targets, glm::vec3(0.0f));
        for (std::size_t k = 0; k < targets; ++k) {
            for (const char* attribute : {"POSITION", "NORMAL"}) {
                const auto it = prim.targets[k].find(attribute);
                if (it == prim.targets[k].end()) continue;
                const std::string twhat = what + " target " + std::to_string(k) + " " + attribute;
                const std::vector<float> d = accessors.floats(it->second, {.type = TINYGLTF_TYPE_VEC3}, twhat);
                if (d.size() / 3 != vertex_count)
                    accessors.fail(twhat + " has " + std::to_string(d.size() / 3) + " elements for " +
                                   std::to_string(vertex_count) + " positions");
                const std::size_t slot = attribute[0] == 'P' ? 0 : 1;
                for (std::size_t v = 0; v < kept.size(); ++v)
                    out.morph_deltas[v * 2 * targets + 2 * k + slot] =
                        glm::vec3(d[3 * kept[v]], d[3 * kept[v] + 1], d[3 * kept[v] + 2]);
            }
        }
        for (std::size_t v = 0; v < kept.size(); ++v) {
            out.vertices[v].morph_first = std::uint32_t(v * 2 * targets);
            out.vertices[v].morph_count = std::uint32_t(targets);
        }
    }
    return out;
}

void append_sources(const GltfPartSources& primitive, GltfPartSources& part) {
    const auto base = std::uint32_t(part.morph_deltas.size());
    for (GltfVertexSource v : primitive.vertices) {
        if (!part.vertices.empty() && part.vertices.front().node != v.node) part.one_node = false;
        v.morph_first += base;
        part.vertices.push_back(v);
    }
    part.morph_deltas.insert(part.morph_deltas.end(), primitive.morph_deltas.begin(), primitive.morph_deltas.end());
    part.skinned = part.skinned || primitive.skinned;
    part.morphed = part.morphed || primitive.morphed;
}

}  // namespace envshadow
