// Off-screen OpenGL 3.3 core renderer on OSMesa (llvmpipe).
// One geometry pass per render, without depth test: every object draws into its own RGBA32F
// target under GL_MIN blending, so each target ends up holding that object's nearest surface
// alone, hidden or not. Per fragment the target receives
//   R = optical-axis depth [m],  G, B, A = (depth bits with the low 8 mantissa bits cleared) | red,
//   green, blue byte of the shaded colour.
// Positive floats order like their bit patterns, so the minimum of G (B, A) is taken by the
// nearest fragment (to 2^-15 relative depth) and carries its colour byte along. The CPU then picks,
// per pixel, the object with the smallest depth: that gives the visible instance, the metric depth
// and the colour; each target's R is the object's own depth (+inf outside: the amodal silhouette).
// Compared with a depth-tested colour pass plus a silhouette pass, this halves the per-triangle
// work, which is what limits llvmpipe on small images.
// A background (a room) has a pass of its own before the objects': depth-tested (hidden
// fragments are not shaded), one RGBA8 colour and one R32F depth target, read back straight into
// the colour and depth images; the objects' merge then overwrites it where an object is nearer.
// The projection maps image row 0 to window row 0, so glReadPixels yields top-down images.
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "occlusion_env/common/errors.hpp"
#include "occlusion_env/render/osmesa_renderer.hpp"
#include "osmesa_library.hpp"

namespace occlusion_env {
namespace {

constexpr double kNearM = 0.05;
constexpr double kFarM = 100.0;
constexpr int kContextBufferSide = 8;  // [px] OSMesa's own colour buffer; we draw into FBOs
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
// The headlight of SceneLighting::headlight, in the optical frame: back and up.
const Eigen::Vector3f kHeadlightToLight(0.0f, -0.316228f, -0.948683f);
static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float), "vertex arrays must be packed");

// Shared by both passes so that both compute bit-identical clip positions and depths.
constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 a_position;  // object frame [m]
layout(location = 1) in vec3 a_color;     // linear RGB
uniform mat4 u_clip_from_object;
uniform mat4 u_optical_from_object;
out vec3 v_position;  // optical frame [m]
out vec3 v_color;
void main() {
  v_position = (u_optical_from_object * vec4(a_position, 1.0)).xyz;
  v_color = a_color;
  gl_Position = u_clip_from_object * vec4(a_position, 1.0);
}
)";

// Flat-shaded vertex colours under a directional light (by default a headlight slightly above the
// camera), sRGB-encoded, packed with the depth as described at the top; +inf (a no-op under GL_MIN)
// into the other targets.
// (kMaxObjects is defined in front of this text: see fragmentShaderSource().)
constexpr const char* kShadingSource = R"(
in vec3 v_position;
in vec3 v_color;
uniform vec3 u_to_light;     // optical frame, unit
uniform vec3 u_light_color;  // of the diffuse term
uniform float u_ambient;
uniform float u_diffuse;
// The fragment's colour in [0, 1], sRGB-encoded.
vec3 shadedColor() {
  vec3 normal = normalize(cross(dFdx(v_position), dFdy(v_position)));
  if (dot(normal, v_position) > 0.0) normal = -normal;  // face the camera: winding is arbitrary
  vec3 shade = u_ambient + u_diffuse * max(dot(normal, u_to_light), 0.0) * u_light_color;
  return pow(clamp(v_color * shade, 0.0, 1.0), vec3(1.0 / 2.2));
}
)";

constexpr const char* kFragmentShaderBody = R"(
uniform int u_object;
layout(location = 0) out vec4 o_target[kMaxObjects];
void main() {
  uvec3 color = uvec3(shadedColor() * 255.0 + 0.5);
  float depth = 1.0 / gl_FragCoord.w;  // optical z [m]
  uint key = floatBitsToUint(depth) & 0xffffff00u;
  vec4 target = vec4(depth, uintBitsToFloat(key | color.r), uintBitsToFloat(key | color.g),
                     uintBitsToFloat(key | color.b));
  vec4 inf = vec4(uintBitsToFloat(0x7f800000u));
  for (int i = 0; i < kMaxObjects; ++i) o_target[i] = (i == u_object) ? target : inf;
}
)";

// The background's pass (depth-tested): the same colour as an object's, and the optical depth.
constexpr const char* kBackgroundShaderBody = R"(
layout(location = 0) out vec4 o_color;   // RGBA8
layout(location = 1) out float o_depth;  // R32F, optical z [m]
void main() {
  o_color = vec4(shadedColor(), 1.0);
  o_depth = 1.0 / gl_FragCoord.w;
}
)";

// Background surfaces lit once per scene (SceneBackground::one_sided under a light fixed in the
// world): each triangle's vertices carry its final colour, so a fragment only writes.
constexpr const char* kPrelitVertexShader = R"(#version 330 core
layout(location = 0) in vec3 a_position;  // object frame [m]
layout(location = 1) in vec3 a_color;     // sRGB-encoded, lit
uniform mat4 u_clip_from_object;
flat out vec3 v_color;
void main() {
  v_color = a_color;
  gl_Position = u_clip_from_object * vec4(a_position, 1.0);
}
)";

constexpr const char* kPrelitFragmentShader = R"(#version 330 core
flat in vec3 v_color;
layout(location = 0) out vec4 o_color;   // RGBA8
layout(location = 1) out float o_depth;  // R32F, optical z [m]
void main() {
  o_color = vec4(v_color, 1.0);
  o_depth = 1.0 / gl_FragCoord.w;
}
)";

// Tiled surfaces (SceneBackground::tiled): one quad, each cell's colour fetched from a texture
// of sRGB-encoded albedos and scaled by the surface's sRGB-encoded light (the encoding x^(1/2.2)
// is multiplicative, so this equals encoding the lit colour).
constexpr const char* kTiledVertexShader = R"(#version 330 core
layout(location = 0) in vec3 a_position;  // world frame [m]
layout(location = 1) in vec3 a_cell;      // cell coordinates (u, v, 0)
uniform mat4 u_clip_from_object;
out vec2 v_cell;
void main() {
  v_cell = a_cell.xy;
  gl_Position = u_clip_from_object * vec4(a_position, 1.0);
}
)";

constexpr const char* kTiledFragmentShader = R"(#version 330 core
in vec2 v_cell;
uniform sampler2D u_cells;   // RGBA32F, sRGB-encoded albedo per cell
uniform vec3 u_gain;         // the surface's light, sRGB-encoded
uniform ivec2 u_last_cell;
layout(location = 0) out vec4 o_color;   // RGBA8
layout(location = 1) out float o_depth;  // R32F, optical z [m]
void main() {
  ivec2 cell = clamp(ivec2(floor(v_cell)), ivec2(0), u_last_cell);
  o_color = vec4(min(texelFetch(u_cells, cell, 0).rgb * u_gain, vec3(1.0)), 1.0);
  o_depth = 1.0 / gl_FragCoord.w;
}
)";

std::string fragmentShaderSource() {
  return "#version 330 core\nconst int kMaxObjects = " + std::to_string(kMaxSceneObjects) + ";" +
         kShadingSource + kFragmentShaderBody;
}

std::string backgroundShaderSource() {
  return std::string("#version 330 core\n") + kShadingSource + kBackgroundShaderBody;
}

void throwOnGlError(const char* where) {
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR) {
    throw RenderError(std::string("OpenGL error ") + std::to_string(error) + " in " + where);
  }
}

GLuint compileShader(GLenum stage, const char* source, const char* what) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    std::array<char, 4096> log{};
    glGetShaderInfoLog(shader, log.size(), nullptr, log.data());
    throw RenderError(std::string("renderer: cannot compile the ") + what +
                      " shader: " + log.data());
  }
  return shader;
}

GLuint linkProgram(const char* fragment_source, const char* what,
                   const char* vertex_source = kVertexShader) {
  const GLuint program = glCreateProgram();
  const GLuint vertex = compileShader(GL_VERTEX_SHADER, vertex_source, "vertex");
  const GLuint fragment = compileShader(GL_FRAGMENT_SHADER, fragment_source, what);
  glAttachShader(program, vertex);
  glAttachShader(program, fragment);
  glLinkProgram(program);
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    std::array<char, 4096> log{};
    glGetProgramInfoLog(program, log.size(), nullptr, log.data());
    throw RenderError(std::string("renderer: cannot link the ") + what + " program: " + log.data());
  }
  return program;
}

GLuint makeRenderbuffer(GLenum format, int width, int height) {
  GLuint renderbuffer = 0;
  glGenRenderbuffers(1, &renderbuffer);
  glBindRenderbuffer(GL_RENDERBUFFER, renderbuffer);
  glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
  return renderbuffer;
}

void throwUnlessComplete(const char* what) {
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throw RenderError(std::string("renderer: the ") + what + " framebuffer is incomplete (status " +
                      std::to_string(status) + ")");
  }
}

// Maps optical-frame points (x right, y down, z forward) [m] to clip space such that pixel
// (column u, row v) in ROS's convention (centres at integers) covers window pixel (u, v): row 0 of
// the read-back image is the image's top row. Depth maps [near, far] to NDC [-1, 1].
Eigen::Matrix4d clipFromOptical(const CameraIntrinsics& k) {
  const double w = k.width, h = k.height;
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  m(0, 0) = 2.0 * k.fx / w;
  m(0, 2) = (2.0 * k.cx + 1.0) / w - 1.0;
  m(1, 1) = 2.0 * k.fy / h;
  m(1, 2) = (2.0 * k.cy + 1.0) / h - 1.0;
  m(2, 2) = (kFarM + kNearM) / (kFarM - kNearM);
  m(2, 3) = -2.0 * kFarM * kNearM / (kFarM - kNearM);
  m(3, 2) = 1.0;
  return m;
}

// (Re)allocates `mat` unless it already is a continuous rows x cols matrix of `type`; true when it
// did, i.e. when the pixels hold nothing yet.
bool ensureMat(cv::Mat& mat, int rows, int cols, int type) {
  if (mat.rows == rows && mat.cols == cols && mat.type() == type && mat.isContinuous()) {
    return false;
  }
  mat.release();
  mat.create(rows, cols, type);
  return true;
}

// Sets the pixels of `rect` in `mat` to `value` (one per channel, of `mat`'s depth).
template <typename Pixel>
void fillRect(cv::Mat& mat, const cv::Rect& rect, Pixel value) {
  for (int row = rect.y; row < rect.y + rect.height; ++row) {
    Pixel* first = mat.ptr<Pixel>(row) + rect.x;
    std::fill(first, first + rect.width, value);
  }
}

void validateTiled(const TiledSurface& surface, const std::string& what) {
  constexpr int kMaxCells = 4096;  // per side; every GL 3.3 implementation takes such textures
  if (surface.cells_u < 1 || surface.cells_v < 1 || surface.cells_u > kMaxCells ||
      surface.cells_v > kMaxCells ||
      surface.colors.size() != static_cast<std::size_t>(surface.cells_u) * surface.cells_v) {
    throw InvalidArgumentError(what + " needs 1.." + std::to_string(kMaxCells) +
                               " cells a side and one colour per cell");
  }
  if (!surface.origin.allFinite() || !(surface.step_u.cross(surface.step_v).norm() > 0.0f)) {
    throw InvalidArgumentError(what + " must be a finite, non-degenerate rectangle");
  }
}

void validatePlaced(const PlacedMesh& placed, const std::string& what) {
  const Mesh* mesh = placed.mesh;
  if (mesh == nullptr || mesh->empty()) throw InvalidArgumentError(what + " has no mesh");
  if (mesh->colors.size() != mesh->positions.size() || mesh->indices.size() % 3 != 0) {
    throw InvalidArgumentError(what + " needs one colour per vertex and whole triangles");
  }
  for (const std::uint32_t index : mesh->indices) {
    if (index >= mesh->positions.size()) throw InvalidArgumentError(what + ": index out of range");
  }
}

// Held while a context is created (with its first GL objects) or destroyed: occlusion_dataset
// --randomize, whose workers make a new renderer whenever a scene's intrinsics change, died once
// in libOSMesa (general protection fault) with two threads doing so (2026-11-25). Rendering itself
// is not serialised.
// Recursive: a constructor that throws destroys its context under the lock it was made under.
std::recursive_mutex& contextLifecycleMutex() {
  static std::recursive_mutex mutex;
  return mutex;
}

// Destroys a context with the copy of libOSMesa that made it (osmesa_library.hpp).
struct ContextDeleter {
  const osmesa::OsMesaLibrary* library = nullptr;
  void operator()(osmesa_context* context) const {
    const std::lock_guard<std::recursive_mutex> lock(contextLifecycleMutex());
    osmesa::destroyContext(*library, context);
  }
};

class OsMesaRenderer final : public Renderer {
 public:
  explicit OsMesaRenderer(const CameraIntrinsics& intrinsics);

  void setScene(const std::vector<PlacedMesh>& objects) override;
  void setBackground(const SceneBackground& background) override;
  void render(const Eigen::Isometry3d& world_from_optical, RenderBuffers& out) override;
  const CameraIntrinsics& intrinsics() const override { return intrinsics_; }
  std::string name() const override { return "osmesa"; }

 private:
  // A tiled surface: its quad (cell coordinates in the colour attribute) and cell texture.
  struct GpuTiles;

  // GL objects of one uploaded mesh.
  struct GpuMesh {
    GLuint vertex_array = 0;
    GLuint positions = 0;
    GLuint colors = 0;
    GLuint indices = 0;
    GLsizei index_count = 0;
    Eigen::Matrix4d world_from_object = Eigen::Matrix4d::Identity();
    Eigen::AlignedBox3d bounds;  // object frame [m]
  };

  // Pixels an object can cover: x, y = first column, row; all of the image when unsure.
  struct PixelRect {
    int x = 0, y = 0, width = 0, height = 0;
  };

  struct GpuTiles {
    GpuMesh quad;
    GLuint texture = 0;
    Eigen::Vector3f normal = Eigen::Vector3f::UnitZ();  // world frame, the side it is seen from
    int last_u = 0, last_v = 0;                         // last cell
  };

  // A linked program and its uniforms (-1 where it has none).
  struct Program {
    GLuint id = 0;
    GLint clip = -1;
    GLint optical = -1;
    GLint object = -1;
    GLint to_light = -1;
    GLint light_color = -1;
    GLint ambient = -1;
    GLint diffuse = -1;
  };

  void makeCurrent();
  // The OpenGL 3.3 core context, made current; checks the implementation's limits.
  void createContext();
  // The shader program, the framebuffer with one target per object and a vertex array per slot.
  void createSceneTargets();
  static void createGpuMesh(GpuMesh& mesh);
  static void upload(const PlacedMesh& placed, GpuMesh& gpu);
  // One vertex per triangle corner, coloured as the objects' shader would colour the triangle's
  // front (the side it is drawn from) under `lighting` (fixed in the world).
  static void uploadPrelit(const PlacedMesh& placed, const SceneLighting& lighting, GpuMesh& gpu);
  static void uploadArrays(const std::vector<Eigen::Vector3f>& positions,
                           const std::vector<Eigen::Vector3f>& colors,
                           const std::vector<std::uint32_t>& indices, GpuMesh& gpu);
  static Program makeProgram(const std::string& fragment_source, const char* what,
                             const char* vertex_source = kVertexShader);
  void createBackgroundTargets();
  static void uploadTiles(const TiledSurface& surface, GpuTiles& gpu);
  void drawTiles(const GpuTiles& tiles, const Eigen::Matrix4d& optical_from_world);
  bool hasBackground() const { return num_background_ + num_tiled_ > 0; }
  void setLighting(const Program& program, const Eigen::Matrix4d& optical_from_world);
  void drawMesh(const Program& program, const GpuMesh& mesh,
                const Eigen::Matrix4d& optical_from_world);
  void renderBackground(const Eigen::Matrix4d& optical_from_world);
  // Colour and depth of the background into out.rgb and out.depth (all of the image).
  void readBackground(RenderBuffers& out);
  PixelRect footprint(const GpuMesh& mesh, const Eigen::Matrix4d& optical_from_object) const;
  // False when the mesh's bounding box lies wholly outside the view (behind the near plane or
  // projecting off the image): such a mesh need not be drawn.
  bool inView(const GpuMesh& mesh, const Eigen::Matrix4d& optical_from_world) const;
  void readBack(RenderBuffers& out);

  CameraIntrinsics intrinsics_;
  std::thread::id owner_thread_;
  osmesa::OsMesaLease llvmpipe_;  // this thread's copy of libOSMesa; outlives context_
  std::array<std::uint8_t, kContextBufferSide * kContextBufferSide * 4> context_buffer_{};
  std::unique_ptr<osmesa_context, ContextDeleter> context_;
  Eigen::Matrix4d clip_from_optical_;

  Program program_;         // the objects' pass
  GLuint framebuffer_ = 0;  // kMaxSceneObjects RGBA32F targets, one per object

  // The background: a depth-tested pass into RGBA8 colour, R32F optical depth and a depth buffer,
  // made on the first setBackground() with meshes.
  Program background_program_;
  Program prelit_program_;  // for one-sided meshes under a light fixed in the world
  Program tiled_program_;
  GLint gain_location_ = -1;
  GLint last_cell_location_ = -1;
  std::vector<GpuTiles> tiled_;
  int num_tiled_ = 0;
  bool prelit_ = false;  // whether the one-sided meshes were uploaded pre-lit
  GLuint background_framebuffer_ = 0;
  std::vector<GpuMesh> background_meshes_;  // one-sided first, then two-sided
  int num_one_sided_ = 0;
  int num_background_ = 0;
  SceneLighting lighting_;
  std::vector<std::uint8_t> background_staging_;  // width * height * 4 once there is a background

  std::array<GpuMesh, kMaxSceneObjects> meshes_;
  int num_objects_ = 0;
  std::array<PixelRect, kMaxSceneObjects> footprints_;  // of the last render
  std::vector<float> staging_;                          // one target read back, width * height * 4
};

OsMesaRenderer::OsMesaRenderer(const CameraIntrinsics& intrinsics)
    : intrinsics_(intrinsics),
      owner_thread_(std::this_thread::get_id()),
      llvmpipe_(owner_thread_),
      context_(nullptr, ContextDeleter{&llvmpipe_.library()}),
      clip_from_optical_(clipFromOptical(intrinsics)) {
  const CameraIntrinsics& k = intrinsics_;
  if (k.width < 1 || k.height < 1 || !(k.fx > 0.0) || !(k.fy > 0.0) || !std::isfinite(k.fx) ||
      !std::isfinite(k.fy) || !std::isfinite(k.cx) || !std::isfinite(k.cy)) {
    throw InvalidArgumentError("renderer: intrinsics need a positive size and focal lengths");
  }
  createContext();
  createSceneTargets();

  // Fixed state for the context's lifetime.
  glDisable(GL_CULL_FACE);   // meshes are not consistently wound
  glDisable(GL_DEPTH_TEST);  // every object's every surface reaches its target
  glEnable(GL_BLEND);
  glBlendEquation(GL_MIN);
  glBlendFunc(GL_ONE, GL_ONE);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glViewport(0, 0, k.width, k.height);
  glFrontFace(GL_CW);  // the projection flips rows: counter-clockwise as seen is clockwise here
  glCullFace(GL_BACK);
  glUseProgram(program_.id);
  staging_.resize(static_cast<std::size_t>(k.width) * k.height * 4);
  throwOnGlError("renderer setup");
}

void OsMesaRenderer::createContext() {
  const CameraIntrinsics& k = intrinsics_;
  const int attributes[] = {OSMESA_FORMAT,
                            OSMESA_RGBA,
                            OSMESA_DEPTH_BITS,
                            0,
                            OSMESA_STENCIL_BITS,
                            0,
                            OSMESA_ACCUM_BITS,
                            0,
                            OSMESA_PROFILE,
                            OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION,
                            3,
                            OSMESA_CONTEXT_MINOR_VERSION,
                            3,
                            0};
  context_.reset(llvmpipe_.library().create_context_attribs(attributes, nullptr));
  if (!context_) throw RenderError("renderer: cannot create an OSMesa OpenGL 3.3 core context");
  makeCurrent();

  GLint max_draw_buffers = 0, max_attachments = 0, max_size = 0;
  glGetIntegerv(GL_MAX_DRAW_BUFFERS, &max_draw_buffers);
  glGetIntegerv(GL_MAX_COLOR_ATTACHMENTS, &max_attachments);
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  if (max_draw_buffers < kMaxSceneObjects || max_attachments < kMaxSceneObjects) {
    throw RenderError("renderer: the GL implementation offers fewer than 8 draw buffers");
  }
  if (k.width > max_size || k.height > max_size) {
    throw InvalidArgumentError("renderer: image size exceeds GL_MAX_RENDERBUFFER_SIZE");
  }
}

void OsMesaRenderer::createSceneTargets() {
  const CameraIntrinsics& k = intrinsics_;
  program_ = makeProgram(fragmentShaderSource(), "scene");

  // One target per object; setScene() enables as many draw buffers as there are objects.
  glGenFramebuffers(1, &framebuffer_);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  for (int i = 0; i < kMaxSceneObjects; ++i) {
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + i, GL_RENDERBUFFER,
                              makeRenderbuffer(GL_RGBA32F, k.width, k.height));
  }
  const GLenum first_buffer = GL_COLOR_ATTACHMENT0;
  glDrawBuffers(1, &first_buffer);
  throwUnlessComplete("scene");

  // One vertex array per scene slot; buffer storage is (re)specified in setScene().
  for (GpuMesh& mesh : meshes_) createGpuMesh(mesh);
  glBindVertexArray(0);
}

OsMesaRenderer::Program OsMesaRenderer::makeProgram(const std::string& fragment_source,
                                                    const char* what, const char* vertex_source) {
  Program program;
  program.id = linkProgram(fragment_source.c_str(), what, vertex_source);
  program.clip = glGetUniformLocation(program.id, "u_clip_from_object");
  program.optical = glGetUniformLocation(program.id, "u_optical_from_object");
  program.object = glGetUniformLocation(program.id, "u_object");
  program.to_light = glGetUniformLocation(program.id, "u_to_light");
  program.light_color = glGetUniformLocation(program.id, "u_light_color");
  program.ambient = glGetUniformLocation(program.id, "u_ambient");
  program.diffuse = glGetUniformLocation(program.id, "u_diffuse");
  return program;
}

void OsMesaRenderer::createBackgroundTargets() {
  const CameraIntrinsics& k = intrinsics_;
  background_program_ = makeProgram(backgroundShaderSource(), "background");
  prelit_program_ = makeProgram(kPrelitFragmentShader, "pre-lit background", kPrelitVertexShader);
  tiled_program_ = makeProgram(kTiledFragmentShader, "tiled background", kTiledVertexShader);
  gain_location_ = glGetUniformLocation(tiled_program_.id, "u_gain");
  last_cell_location_ = glGetUniformLocation(tiled_program_.id, "u_last_cell");
  glGenFramebuffers(1, &background_framebuffer_);
  glBindFramebuffer(GL_FRAMEBUFFER, background_framebuffer_);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                            makeRenderbuffer(GL_RGBA8, k.width, k.height));
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER,
                            makeRenderbuffer(GL_R32F, k.width, k.height));
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                            makeRenderbuffer(GL_DEPTH_COMPONENT32F, k.width, k.height));
  static constexpr GLenum kBuffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glDrawBuffers(2, kBuffers);
  throwUnlessComplete("background");
  background_staging_.resize(static_cast<std::size_t>(k.width) * k.height * 4);
}

void OsMesaRenderer::makeCurrent() {
  if (std::this_thread::get_id() != owner_thread_) {
    throw RenderError("renderer: called from a thread other than the one that created it");
  }
  if (!osmesa::makeCurrent(llvmpipe_.library(), context_.get(), context_buffer_.data(),
                           kContextBufferSide, kContextBufferSide)) {
    throw RenderError("renderer: OSMesaMakeCurrent failed");
  }
}

void OsMesaRenderer::setScene(const std::vector<PlacedMesh>& objects) {
  if (objects.size() > static_cast<std::size_t>(kMaxSceneObjects)) {
    throw InvalidArgumentError("renderer: a scene holds at most 8 objects, got " +
                               std::to_string(objects.size()));
  }
  // Validate everything before touching GL state, so a rejected scene leaves the old one intact.
  for (std::size_t i = 0; i < objects.size(); ++i) {
    validatePlaced(objects[i], "renderer: scene object " + std::to_string(i));
  }
  makeCurrent();
  for (std::size_t i = 0; i < objects.size(); ++i) upload(objects[i], meshes_[i]);
  glBindVertexArray(0);
  num_objects_ = static_cast<int>(objects.size());
  if (num_objects_ > 0) {
    // Fragment output i goes to target i: one per object.
    static constexpr GLenum kBuffers[kMaxSceneObjects] = {
        GL_COLOR_ATTACHMENT0,     GL_COLOR_ATTACHMENT0 + 1, GL_COLOR_ATTACHMENT0 + 2,
        GL_COLOR_ATTACHMENT0 + 3, GL_COLOR_ATTACHMENT0 + 4, GL_COLOR_ATTACHMENT0 + 5,
        GL_COLOR_ATTACHMENT0 + 6, GL_COLOR_ATTACHMENT0 + 7};
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    glDrawBuffers(num_objects_, kBuffers);
  }
  throwOnGlError("setScene");
}

void OsMesaRenderer::createGpuMesh(GpuMesh& mesh) {
  glGenVertexArrays(1, &mesh.vertex_array);
  glGenBuffers(1, &mesh.positions);
  glGenBuffers(1, &mesh.colors);
  glGenBuffers(1, &mesh.indices);
  glBindVertexArray(mesh.vertex_array);
  glBindBuffer(GL_ARRAY_BUFFER, mesh.positions);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, mesh.colors);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(1);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, mesh.indices);
}

void OsMesaRenderer::uploadArrays(const std::vector<Eigen::Vector3f>& positions,
                                  const std::vector<Eigen::Vector3f>& colors,
                                  const std::vector<std::uint32_t>& indices, GpuMesh& gpu) {
  glBindVertexArray(gpu.vertex_array);
  glBindBuffer(GL_ARRAY_BUFFER, gpu.positions);
  glBufferData(GL_ARRAY_BUFFER, positions.size() * sizeof(Eigen::Vector3f), positions.data(),
               GL_STATIC_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, gpu.colors);
  glBufferData(GL_ARRAY_BUFFER, colors.size() * sizeof(Eigen::Vector3f), colors.data(),
               GL_STATIC_DRAW);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, indices.size() * sizeof(std::uint32_t), indices.data(),
               GL_STATIC_DRAW);
  gpu.index_count = static_cast<GLsizei>(indices.size());
}

void OsMesaRenderer::upload(const PlacedMesh& placed, GpuMesh& gpu) {
  const Mesh& mesh = *placed.mesh;
  uploadArrays(mesh.positions, mesh.colors, mesh.indices, gpu);
  gpu.world_from_object = placed.world_from_object.matrix();
  gpu.bounds = boundingBox(mesh).cast<double>();
}

void OsMesaRenderer::uploadPrelit(const PlacedMesh& placed, const SceneLighting& lighting,
                                  GpuMesh& gpu) {
  const Mesh& mesh = *placed.mesh;
  const Eigen::Matrix3f world_from_object = placed.world_from_object.linear().cast<float>();
  const Eigen::Vector3f to_light = lighting.to_light_world.normalized().cast<float>();
  Mesh lit;
  lit.positions.reserve(mesh.indices.size());
  lit.colors.reserve(mesh.indices.size());
  lit.indices.reserve(mesh.indices.size());
  for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const Eigen::Vector3f& a = mesh.positions[mesh.indices[t]];
    const Eigen::Vector3f& b = mesh.positions[mesh.indices[t + 1]];
    const Eigen::Vector3f& c = mesh.positions[mesh.indices[t + 2]];
    // Counter-clockwise seen from the front: (b - a) x (c - a) points at the viewer.
    const Eigen::Vector3f normal = (world_from_object * (b - a).cross(c - a)).normalized();
    const float facing = normal.allFinite() ? std::max(normal.dot(to_light), 0.0f) : 0.0f;
    const Eigen::Vector3f shade =
        Eigen::Vector3f::Constant(lighting.ambient) + lighting.diffuse * facing * lighting.color;
    for (int corner = 0; corner < 3; ++corner) {
      const std::uint32_t index = mesh.indices[t + corner];
      const Eigen::Vector3f linear =
          mesh.colors[index].cwiseProduct(shade).cwiseMax(0.0f).cwiseMin(1.0f);
      lit.colors.push_back(linear.unaryExpr([](float v) { return std::pow(v, 1.0f / 2.2f); }));
      lit.positions.push_back(mesh.positions[index]);
      lit.indices.push_back(static_cast<std::uint32_t>(lit.indices.size()));
    }
  }
  uploadArrays(lit.positions, lit.colors, lit.indices, gpu);
  gpu.world_from_object = placed.world_from_object.matrix();
  gpu.bounds = boundingBox(mesh).cast<double>();
}

void OsMesaRenderer::setBackground(const SceneBackground& background) {
  const std::size_t count = background.one_sided.size() + background.two_sided.size();
  for (std::size_t i = 0; i < count; ++i) {
    const PlacedMesh& placed = i < background.one_sided.size()
                                   ? background.one_sided[i]
                                   : background.two_sided[i - background.one_sided.size()];
    validatePlaced(placed, "renderer: background mesh " + std::to_string(i));
  }
  for (std::size_t i = 0; i < background.tiled.size(); ++i) {
    validateTiled(background.tiled[i], "renderer: tiled surface " + std::to_string(i));
  }
  if (!background.lighting.to_light_world.allFinite() || !background.lighting.color.allFinite() ||
      !std::isfinite(background.lighting.ambient) || !std::isfinite(background.lighting.diffuse)) {
    throw InvalidArgumentError("renderer: the lighting must be finite");
  }
  makeCurrent();
  if (count + background.tiled.size() > 0 && background_framebuffer_ == 0) {
    createBackgroundTargets();
  }
  while (tiled_.size() < background.tiled.size()) {
    tiled_.emplace_back();
    createGpuMesh(tiled_.back().quad);
    glGenTextures(1, &tiled_.back().texture);
  }
  for (std::size_t i = 0; i < background.tiled.size(); ++i)
    uploadTiles(background.tiled[i], tiled_[i]);
  num_tiled_ = static_cast<int>(background.tiled.size());
  while (background_meshes_.size() < count) {
    background_meshes_.emplace_back();
    createGpuMesh(background_meshes_.back());
  }
  // Under a light fixed in the world a one-sided surface always shows the same side, so its
  // colours can be lit once here; a headlight moves with the camera.
  prelit_ = !background.lighting.headlight;
  for (std::size_t i = 0; i < count; ++i) {
    if (i < background.one_sided.size()) {
      if (prelit_) {
        uploadPrelit(background.one_sided[i], background.lighting, background_meshes_[i]);
      } else {
        upload(background.one_sided[i], background_meshes_[i]);
      }
    } else {
      upload(background.two_sided[i - background.one_sided.size()], background_meshes_[i]);
    }
  }
  glBindVertexArray(0);
  num_one_sided_ = static_cast<int>(background.one_sided.size());
  num_background_ = static_cast<int>(count);
  lighting_ = background.lighting;
  throwOnGlError("setBackground");
}

void OsMesaRenderer::uploadTiles(const TiledSurface& surface, GpuTiles& gpu) {
  const Eigen::Vector3f u = surface.step_u * static_cast<float>(surface.cells_u);
  const Eigen::Vector3f v = surface.step_v * static_cast<float>(surface.cells_v);
  const Eigen::Vector3f& o = surface.origin;
  const float cu = static_cast<float>(surface.cells_u), cv = static_cast<float>(surface.cells_v);
  // Counter-clockwise seen from the side step_u x step_v points to.
  const std::vector<Eigen::Vector3f> corners = {o, o + u, o + u + v, o + v};
  uploadArrays(corners,
               {Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(cu, 0, 0), Eigen::Vector3f(cu, cv, 0),
                Eigen::Vector3f(0, cv, 0)},
               {0, 1, 2, 0, 2, 3}, gpu.quad);
  gpu.quad.world_from_object = Eigen::Matrix4d::Identity();
  gpu.quad.bounds = Eigen::AlignedBox3d(o.cast<double>());
  for (const Eigen::Vector3f& corner : corners) gpu.quad.bounds.extend(corner.cast<double>());
  gpu.normal = surface.step_u.cross(surface.step_v).normalized();
  gpu.last_u = surface.cells_u - 1;
  gpu.last_v = surface.cells_v - 1;
  std::vector<float> texels;  // sRGB-encoded albedo, RGBA
  texels.reserve(surface.colors.size() * 4);
  for (const Eigen::Vector3f& color : surface.colors) {
    for (int c = 0; c < 3; ++c)
      texels.push_back(std::pow(std::clamp(color[c], 0.0f, 1.0f), 1.0f / 2.2f));
    texels.push_back(1.0f);
  }
  glBindTexture(GL_TEXTURE_2D, gpu.texture);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, surface.cells_u, surface.cells_v, 0, GL_RGBA, GL_FLOAT,
               texels.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
}

void OsMesaRenderer::drawTiles(const GpuTiles& tiles, const Eigen::Matrix4d& optical_from_world) {
  // The objects' shading for the surface's normal, sRGB-encoded (see kTiledFragmentShader).
  const SceneLighting& light = lighting_;
  const Eigen::Vector3f normal =
      light.headlight
          ? (optical_from_world.topLeftCorner<3, 3>().cast<float>() * tiles.normal).eval()
          : tiles.normal;
  const Eigen::Vector3f to_light =
      light.headlight ? kHeadlightToLight : light.to_light_world.normalized().cast<float>();
  const float facing = std::max(normal.dot(to_light), 0.0f);
  const Eigen::Vector3f shade =
      Eigen::Vector3f::Constant(light.ambient) + light.diffuse * facing * light.color;
  glUniform3f(gain_location_, std::pow(std::max(shade.x(), 0.0f), 1.0f / 2.2f),
              std::pow(std::max(shade.y(), 0.0f), 1.0f / 2.2f),
              std::pow(std::max(shade.z(), 0.0f), 1.0f / 2.2f));
  glUniform2i(last_cell_location_, tiles.last_u, tiles.last_v);
  glBindTexture(GL_TEXTURE_2D, tiles.texture);
  drawMesh(tiled_program_, tiles.quad, optical_from_world);
}

void OsMesaRenderer::setLighting(const Program& program,
                                 const Eigen::Matrix4d& optical_from_world) {
  const SceneLighting& light = lighting_;
  const Eigen::Vector3f to_light =
      light.headlight
          ? kHeadlightToLight
          : (optical_from_world.topLeftCorner<3, 3>() * light.to_light_world.normalized())
                .cast<float>()
                .eval();
  glUniform3f(program.to_light, to_light.x(), to_light.y(), to_light.z());
  glUniform3f(program.light_color, light.color.x(), light.color.y(), light.color.z());
  glUniform1f(program.ambient, light.ambient);
  glUniform1f(program.diffuse, light.diffuse);
}

void OsMesaRenderer::drawMesh(const Program& program, const GpuMesh& mesh,
                              const Eigen::Matrix4d& optical_from_world) {
  const Eigen::Matrix4d optical_from_object = optical_from_world * mesh.world_from_object;
  const Eigen::Matrix4f clip_from_object = (clip_from_optical_ * optical_from_object).cast<float>();
  const Eigen::Matrix4f optical = optical_from_object.cast<float>();
  glUniformMatrix4fv(program.clip, 1, GL_FALSE, clip_from_object.data());
  glUniformMatrix4fv(program.optical, 1, GL_FALSE, optical.data());
  glBindVertexArray(mesh.vertex_array);
  glDrawElements(GL_TRIANGLES, mesh.index_count, GL_UNSIGNED_INT, nullptr);
}

void OsMesaRenderer::renderBackground(const Eigen::Matrix4d& optical_from_world) {
  static constexpr float kBlack[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  static constexpr float kNothing[4] = {kNaN, kNaN, kNaN, kNaN};  // REP 118: no depth
  static constexpr float kFarthest = 1.0f;
  glBindFramebuffer(GL_FRAMEBUFFER, background_framebuffer_);
  glUseProgram(background_program_.id);
  setLighting(background_program_, optical_from_world);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
  glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glColorMaski(1, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glClearBufferfv(GL_COLOR, 0, kBlack);
  glClearBufferfv(GL_COLOR, 1, kNothing);
  glClearBufferfv(GL_DEPTH, 0, &kFarthest);
  // Clutter first, then the tiled surfaces in their order (a room gives walls before the floor),
  // then other one-sided meshes: what lies behind drawn surfaces fails the depth test before it
  // is shaded. Clutter out of view is not drawn at all.
  for (int i = num_one_sided_; i < num_background_; ++i) {
    if (inView(background_meshes_[i], optical_from_world)) {
      drawMesh(background_program_, background_meshes_[i], optical_from_world);
    }
  }
  glEnable(GL_CULL_FACE);
  glUseProgram(tiled_program_.id);
  for (int i = 0; i < num_tiled_; ++i) drawTiles(tiled_[i], optical_from_world);
  const Program& one_sided = prelit_ ? prelit_program_ : background_program_;
  glUseProgram(one_sided.id);
  for (int i = num_one_sided_ - 1; i >= 0; --i) {
    drawMesh(one_sided, background_meshes_[i], optical_from_world);
  }
  glDisable(GL_CULL_FACE);
  glDisable(GL_DEPTH_TEST);
  glEnable(GL_BLEND);
  glUseProgram(program_.id);
}

void OsMesaRenderer::readBackground(RenderBuffers& out) {
  const int width = intrinsics_.width, height = intrinsics_.height;
  glBindFramebuffer(GL_FRAMEBUFFER, background_framebuffer_);
  glReadBuffer(GL_COLOR_ATTACHMENT1);
  glReadPixels(0, 0, width, height, GL_RED, GL_FLOAT, out.depth.data);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, background_staging_.data());
  const std::uint8_t* rgba = background_staging_.data();
  std::uint8_t* rgb = out.rgb.data;
  const std::size_t num_pixels = static_cast<std::size_t>(width) * height;
  for (std::size_t p = 0; p < num_pixels; ++p) {
    rgb[3 * p] = rgba[4 * p];
    rgb[3 * p + 1] = rgba[4 * p + 1];
    rgb[3 * p + 2] = rgba[4 * p + 2];
  }
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
}

bool OsMesaRenderer::inView(const GpuMesh& mesh, const Eigen::Matrix4d& optical_from_world) const {
  const Eigen::Matrix4d optical_from_object = optical_from_world * mesh.world_from_object;
  bool all_behind = true;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d point_object =
        mesh.bounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner));
    const double z = (optical_from_object * point_object.homogeneous()).z();
    all_behind = all_behind && z <= kNearM;
  }
  return !all_behind && footprint(mesh, optical_from_object).width > 0;
}

OsMesaRenderer::PixelRect OsMesaRenderer::footprint(
    const GpuMesh& mesh, const Eigen::Matrix4d& optical_from_object) const {
  const PixelRect whole{0, 0, intrinsics_.width, intrinsics_.height};
  double u_min = kInf, u_max = -kInf, v_min = kInf, v_max = -kInf;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d point_object =
        mesh.bounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner));
    const Eigen::Vector3d point = (optical_from_object * point_object.homogeneous()).head<3>();
    if (point.z() <= kNearM) return whole;  // crosses the near plane: no cheap bound
    const Eigen::Vector2d pixel = intrinsics_.project(point);
    u_min = std::min(u_min, pixel.x());
    u_max = std::max(u_max, pixel.x());
    v_min = std::min(v_min, pixel.y());
    v_max = std::max(v_max, pixel.y());
  }
  // The box's corners bound its projection; one pixel of margin covers rasterisation rounding.
  const int x0 = std::max(0, static_cast<int>(std::floor(u_min)) - 1);
  const int y0 = std::max(0, static_cast<int>(std::floor(v_min)) - 1);
  const int x1 = std::min(intrinsics_.width, static_cast<int>(std::ceil(u_max)) + 2);
  const int y1 = std::min(intrinsics_.height, static_cast<int>(std::ceil(v_max)) + 2);
  if (x1 <= x0 || y1 <= y0) return {0, 0, 0, 0};  // off screen
  return {x0, y0, x1 - x0, y1 - y0};
}

void OsMesaRenderer::render(const Eigen::Isometry3d& world_from_optical, RenderBuffers& out) {
  makeCurrent();
  const Eigen::Matrix4d optical_from_world = world_from_optical.inverse(Eigen::Isometry).matrix();
  static constexpr float kInfs[4] = {kInf, kInf, kInf, kInf};
  if (hasBackground()) renderBackground(optical_from_world);
  setLighting(program_, optical_from_world);
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  // Each object only touches the pixels of its bounding box's projection: clear, draw and read
  // back just those (objects typically cover a fraction of the image).
  glEnable(GL_SCISSOR_TEST);
  for (int i = 0; i < num_objects_; ++i) {
    const GpuMesh& mesh = meshes_[i];
    const Eigen::Matrix4d optical_from_object = optical_from_world * mesh.world_from_object;
    const PixelRect rect = footprint(mesh, optical_from_object);
    footprints_[i] = rect;
    if (rect.width == 0) continue;
    // The other targets would only receive +inf, a no-op under GL_MIN: masking them spares
    // llvmpipe their per-fragment blending. The clear below obeys the mask too.
    for (int target = 0; target < num_objects_; ++target) {
      const GLboolean on = target == i ? GL_TRUE : GL_FALSE;
      glColorMaski(target, on, on, on, on);
    }
    glScissor(rect.x, rect.y, rect.width, rect.height);
    glClearBufferfv(GL_COLOR, i, kInfs);
    glUniform1i(program_.object, i);
    drawMesh(program_, mesh, optical_from_world);
  }
  glDisable(GL_SCISSOR_TEST);
  readBack(out);
  throwOnGlError("render");
}

void OsMesaRenderer::readBack(RenderBuffers& out) {
  const int width = intrinsics_.width, height = intrinsics_.height;
  const cv::Rect image(0, 0, width, height);
  // Outside out.footprint (out.target_footprint) the images (the targets' images) still hold the
  // background from the last render into them, unless they are new: then nothing is known.
  bool allocated = false;
  allocated |= ensureMat(out.rgb, height, width, CV_8UC3);
  allocated |= ensureMat(out.instance, height, width, CV_8UC1);
  allocated |= ensureMat(out.depth, height, width, CV_32FC1);
  allocated |= ensureMat(out.amodal_bits, height, width, CV_8UC1);
  cv::Rect footprint;  // union of the objects' footprints [px]
  for (int i = 0; i < num_objects_; ++i) {
    const PixelRect& rect = footprints_[i];
    footprint |= cv::Rect(rect.x, rect.y, rect.width, rect.height);
  }
  // Per-pixel work stays inside the footprints of this render and the last one: the rest of every
  // image already is background. A room covers every pixel of colour and depth: it is read back
  // whole, and the objects are merged into it.
  if (hasBackground()) {
    readBackground(out);
  } else {
    const cv::Rect dirty = (allocated ? image : out.footprint & image) | footprint;
    fillRect(out.depth, dirty, kNaN);  // REP 118: nothing hit
    fillRect(out.rgb, dirty, cv::Vec3b(0, 0, 0));
  }
  const cv::Rect dirty = (allocated ? image : out.target_footprint & image) | footprint;
  fillRect(out.instance, dirty, std::uint8_t{0});
  fillRect(out.amodal_bits, dirty, std::uint8_t{0});
  if (out.object_depth.size() != static_cast<std::size_t>(num_objects_)) {
    out.object_depth.resize(num_objects_);
  }
  for (cv::Mat& object_depth : out.object_depth) {
    const bool is_new = ensureMat(object_depth, height, width, CV_32FC1);
    fillRect(object_depth, is_new ? image : dirty, kInf);
  }

  // Merge the targets one by one: each gives its object's depth, silhouette bit and, where it is
  // the nearest so far, the visible instance and colour.
  float* nearest = reinterpret_cast<float*>(out.depth.data);  // NaN where nothing is hit yet
  std::uint8_t* rgb = out.rgb.data;
  std::uint8_t* instance = out.instance.data;
  std::uint8_t* bits = out.amodal_bits.data;
  for (int i = 0; i < num_objects_; ++i) {
    float* object_depth = reinterpret_cast<float*>(out.object_depth[i].data);
    const PixelRect& rect = footprints_[i];
    if (rect.width == 0) continue;
    glReadBuffer(GL_COLOR_ATTACHMENT0 + i);
    glReadPixels(rect.x, rect.y, rect.width, rect.height, GL_RGBA, GL_FLOAT, staging_.data());
    const std::uint8_t bit = static_cast<std::uint8_t>(1u << i);
    for (int row = 0; row < rect.height; ++row) {
      const float* target = staging_.data() + static_cast<std::size_t>(row) * rect.width * 4;
      const std::size_t first = static_cast<std::size_t>(rect.y + row) * width + rect.x;
      for (int col = 0; col < rect.width; ++col, target += 4) {
        const float depth = target[0];
        if (!(depth < kInf)) continue;
        const std::size_t p = first + col;
        object_depth[p] = depth;
        bits[p] |= bit;
        // True for the first hit (nearest is NaN) and for every nearer one after it.
        if (!(nearest[p] <= depth)) {
          nearest[p] = depth;
          instance[p] = static_cast<std::uint8_t>(i + 1);
          for (int c = 0; c < 3; ++c) {
            std::uint32_t packed;
            std::memcpy(&packed, &target[1 + c], sizeof packed);
            rgb[3 * p + c] = static_cast<std::uint8_t>(packed & 0xffu);
          }
        }
      }
    }
  }
  out.footprint = hasBackground() ? image : footprint;
  out.target_footprint = footprint;
}

}  // namespace

std::unique_ptr<Renderer> makeOsMesaRenderer(const CameraIntrinsics& intrinsics,
                                             const RendererOptions& options) {
  if (options.rasterizer_threads < 0 || options.rasterizer_threads > 64) {
    throw InvalidArgumentError("renderer: rasterizer_threads must be in [0, 64], got " +
                               std::to_string(options.rasterizer_threads));
  }
  // llvmpipe reads LP_NUM_THREADS once per process, when the first context is created: the first
  // renderer fixes it, and a later one cannot change it.
  static std::mutex mutex;
  static int process_threads = -1;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (process_threads < 0) {
      process_threads = options.rasterizer_threads;
      setenv("LP_NUM_THREADS", std::to_string(process_threads).c_str(), /*overwrite=*/1);
    } else if (process_threads != options.rasterizer_threads) {
      throw InvalidArgumentError(
          "renderer: llvmpipe already runs with " + std::to_string(process_threads) +
          " rasteriser threads in this process (read once, at the first context); asked for " +
          std::to_string(options.rasterizer_threads));
    }
  }
  const std::lock_guard<std::recursive_mutex> lock(contextLifecycleMutex());
  return std::make_unique<OsMesaRenderer>(intrinsics);
}

}  // namespace occlusion_env
