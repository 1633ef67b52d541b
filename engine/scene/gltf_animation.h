#pragma once
// glTF animation, skins and morph targets (docs/DESIGN.md §6), posed on the CPU at the scene clock.
// A GltfRig holds the node hierarchy's rest transforms, the skins and the animation clips of one
// file; a MeshDeformation holds, for one GltfPart, where each of its vertices came from (node,
// mesh-space position and normal, joints and weights, morph deltas) and poses it:
//   p = sum_j w_j (G(joint_j) IBM_j) (p0 + sum_k m_k dp_k)   skinned (glTF 2.0 §3.7.3)
//   p = G(node) (p0 + sum_k m_k dp_k)                         not skinned
// with G the node's model-space matrix at the clip's time and m_k the node's morph weights (animated,
// or the node's or mesh's defaults). Normals are skinned, not recomputed: n0 + sum m_k dn_k through the
// inverse transpose of the blended matrix, normalised; tangents through the blended matrix itself, made
// orthogonal to the posed normal (morph targets' TANGENT deltas are not read). Other per-vertex arrays of the
// mesh (texture coordinates) are copied unchanged from the bind mesh. No GL.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "scene/scene.h"

namespace tinygltf {
class Model;
}

namespace envshadow {

class GltfAccessors;

enum class GltfInterpolation { step, linear, cubic_spline };

// One sampler: keyframe times (strictly increasing) and `components` floats per output element
// (3 for translation and scale, 4 for rotation, the morph target count for weights); cubic splines
// hold in-tangent, value, out-tangent per key (glTF 2.0 Appendix C).
struct GltfSampler {
    GltfInterpolation interpolation = GltfInterpolation::linear;
    std::vector<float> input;
    std::vector<float> output;
    int components = 0;
    // The value at time t (clamped to the keys), `components` floats; rotations are slerped (LINEAR)
    // or normalised (CUBICSPLINE).
    void sample(double t, bool rotation, float* out) const;
};

struct GltfChannel {
    enum class Path { translation, rotation, scale, weights };
    int node = 0;
    Path path = Path::translation;
    int sampler = 0;
};

struct GltfClip {
    std::string name;
    std::vector<GltfSampler> samplers;
    std::vector<GltfChannel> channels;
    double duration = 0.0;  // the last key time over all samplers
};

struct GltfNode {
    int parent = -1;
    bool has_matrix = false;  // `matrix` nodes are not animated (glTF 2.0 §3.7.2.1)
    glm::mat4 matrix{1.0f};
    glm::vec3 translation{0.0f}, scale{1.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
    std::vector<float> weights;  // morph weights: the node's, else its mesh's; empty without targets
};

struct GltfSkin {
    std::vector<int> joints;              // node indices
    std::vector<glm::mat4> inverse_bind;  // one per joint (identity when the file gives none)
};

// The node hierarchy (parents before children in `order`), skins and clips of one file.
struct GltfRig {
    std::vector<GltfNode> nodes;
    std::vector<int> order;  // nodes reachable from the scene's roots, each after its parent
    std::vector<GltfSkin> skins;
    std::vector<GltfClip> clips;

    // Model-space matrix of every node, and every node's morph weights, at time t of clip `clip`
    // (-1: the rest pose); t is the clip's own time (already looped or clamped).
    void pose(int clip, double t, std::vector<glm::mat4>& world, std::vector<std::vector<float>>& weights) const;
};

// Where one vertex of a part came from.
struct GltfVertexSource {
    glm::vec3 position{0.0f}, normal{0.0f};  // mesh space
    glm::vec4 tangent{0.0f};                 // mesh space, where the part has tangents (Mesh::tangents)
    std::uint32_t node = 0;                  // the node that instances the mesh
    std::int32_t skin = -1;                  // the node's skin, -1 for none
    glm::uvec4 joints{0};                    // indices into the skin's joints
    glm::vec4 weights{0.0f};                 // normalised to sum 1
    std::uint32_t morph_first = 0;           // into GltfPartSources::morph_deltas: per target, dp then dn
    std::uint32_t morph_count = 0;           // targets of the vertex's primitive
};

struct GltfPartSources {
    std::vector<GltfVertexSource> vertices;  // one per vertex of the part's Mesh
    std::vector<glm::vec3> morph_deltas;
    bool skinned = false, morphed = false;
    bool one_node = true;  // every vertex from the same node
};

// A glTF part's deformation by one clip. `loop`: times wrap over the clip's duration, else they clamp
// to [0, duration].
class MeshDeformation {
public:
    MeshDeformation(std::shared_ptr<const GltfRig> rig, std::shared_ptr<const GltfPartSources> sources,
                    std::shared_ptr<const Mesh> bind, int clip, bool loop);

    double duration() const;
    double clip_time(double t) const;
    // Only node motion of a single node: the mesh stays the bind mesh and moves by rigid_motion(t).
    bool rigid() const { return rigid_; }
    // The node's model-space matrix at t times its inverse at rest (rigid() only).
    glm::mat4 rigid_motion(double t) const;
    // The posed mesh at time t (the last one is kept: the renderer and the planner ask for the same t).
    std::shared_ptr<const Mesh> mesh_at(double t) const;
    // The part's vertices at clip time `clip_t` into `mesh` (positions, normals, bounds).
    void pose_into(double clip_t, Mesh& mesh) const;

private:
    std::shared_ptr<const GltfRig> rig_;
    std::shared_ptr<const GltfPartSources> sources_;
    std::shared_ptr<const Mesh> bind_;
    int clip_;
    bool loop_;
    bool rigid_;
    glm::mat4 rest_inverse_{1.0f};
    mutable std::mutex mutex_;
    mutable double cached_time_ = 0.0;
    mutable std::shared_ptr<Mesh>
        cached_;  // a pose (null until one is asked for), reused in place once no caller holds it
};

// Reading (scene/gltf.cpp), every failure an InputError naming the file: the rig of `model` (nodes,
// skins with their inverse bind matrices, clips with checked samplers and channels), and the sources of
// the kept vertices `kept` (accessor elements) of one primitive instanced by node `node`, with their
// mesh-space positions and normals already read.
GltfRig read_gltf_rig(const GltfAccessors& accessors, const tinygltf::Model& model);
GltfPartSources read_primitive_sources(const GltfAccessors& accessors, const tinygltf::Model& model, const GltfRig& rig,
                                       int node, int mesh, int primitive, const std::vector<std::uint32_t>& kept,
                                       std::vector<glm::vec3> positions, std::vector<glm::vec3> normals);
// Appends `primitive`'s sources to `part`'s (their vertices follow the part's).
void append_sources(const GltfPartSources& primitive, GltfPartSources& part);

// The part's vertices posed by `rig` at the rest pose (skins and default morph weights applied).
void pose_rest(const GltfRig& rig, const GltfPartSources& sources, Mesh& mesh);

}  // namespace envshadow
