// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// read_mesh_file() of mesh.hpp: assimp in a child process, its answer
// checked by the parent.
#include "cellguard/host/io/mesh.hpp"

#include <poll.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <exception>

namespace cellguard::host {

namespace {

constexpr std::uint32_t kAnswerMagic = 0x4853454DU;  // "MESH"
constexpr std::size_t kMessageBytes = 400U;
constexpr std::uint32_t kRead = 0U;     ///< the answer's code: vertices follow
constexpr std::uint32_t kRefused = 1U;  ///< the answer's code: the message says why

/// The child's answer: a fixed header, then 3 doubles per vertex.
struct AnswerHeader {
    std::uint32_t magic = kAnswerMagic;
    std::uint32_t code = 0U;  ///< kRead or kRefused
    char message[kMessageBytes] = {};
    double unit = 1.0;
    std::uint64_t faces = 0U;
    std::uint64_t vertices = 0U;
};

std::string lower_suffix(const std::string& path) {
    const std::size_t dot = path.find_last_of('.');
    std::string s = dot == std::string::npos ? std::string() : path.substr(dot + 1U);
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

// ---------------------------------------------------------------- the child

bool write_all(int fd, const void* data, std::size_t size) {
    const auto* p = static_cast<const char*>(data);
    while (size > 0U) {
        const ssize_t n = ::write(fd, p, size);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            return false;
        }
        p += n;
        size -= static_cast<std::size_t>(n);
    }
    return true;
}

/// The root's uniform scale (the file's unit), or a negative value when the
/// root's 3 x 3 part is not a rotation times a uniform scale.
double root_scale(const aiMatrix4x4& m) {
    Eigen::Matrix4d t;
    for (unsigned r = 0U; r < 4U; ++r) {
        const ai_real* row = m[r];
        for (unsigned c = 0U; c < 4U; ++c) {
            t(r, c) = static_cast<double>(row[c]);
        }
    }
    const Eigen::Matrix3d a = t.topLeftCorner<3, 3>();
    const double s = std::cbrt(std::abs(a.determinant()));
    const bool rotation_and_scale = s > 0.0 && std::isfinite(s) && (a.transpose() * a / (s * s)).isIdentity(1e-6);
    const bool no_translation = t.topRightCorner<3, 1>().isZero(0.0);
    return rotation_and_scale && no_translation ? s : -1.0;
}

/// Every vertex of every node's meshes, each placed by its node's transform
/// composed with its ancestors' (from @p root_at at the root); depth first
/// on an explicit stack, so a deeply nested file cannot exhaust the child's.
void collect(const aiScene& scene, const aiMatrix4x4& root_at, std::vector<double>& out, std::uint64_t& faces) {
    std::vector<std::pair<const aiNode*, aiMatrix4x4>> stack{{scene.mRootNode, root_at}};
    while (!stack.empty() && out.size() <= 3U * kMeshMaxVertices) {
        const auto [node, at] = stack.back();
        stack.pop_back();
        for (unsigned k = 0U; k < node->mNumMeshes; ++k) {
            const aiMesh& mesh = *scene.mMeshes[node->mMeshes[k]];
            faces += mesh.mNumFaces;
            for (unsigned v = 0U; v < mesh.mNumVertices && out.size() <= 3U * kMeshMaxVertices; ++v) {
                const aiVector3D p = at * mesh.mVertices[v];
                out.insert(out.end(), {static_cast<double>(p.x), static_cast<double>(p.y), static_cast<double>(p.z)});
            }
        }
        for (unsigned c = 0U; c < node->mNumChildren; ++c) {
            stack.emplace_back(node->mChildren[c], at * node->mChildren[c]->mTransformation);
        }
    }
}

bool write_answer(int fd, const AnswerHeader& h, const std::vector<double>& xyz) {
    return write_all(fd, &h, sizeof(h)) && write_all(fd, xyz.data(), xyz.size() * sizeof(double));
}

/// The mesh library's child: reads @p path with assimp and answers on @p fd.
int assimp_child(const char* path, int fd) {
    AnswerHeader h;
    std::vector<double> xyz;
    try {
        Assimp::Importer importer;
        const aiScene* scene = importer.ReadFile(path, aiProcess_ValidateDataStructure);
        const double unit = scene != nullptr && scene->mRootNode != nullptr
                                ? root_scale(scene->mRootNode->mTransformation)
                                : 1.0;
        if (scene == nullptr || scene->mRootNode == nullptr) {
            h.code = kRefused;
            static_cast<void>(std::snprintf(h.message, sizeof(h.message), "the mesh library cannot read it: %s",
                                            importer.GetErrorString()));
        } else if (unit < 0.0) {
            h.code = kRefused;
            static_cast<void>(std::snprintf(h.message, sizeof(h.message),
                                            "its root transform is not a rotation and a uniform scale"));
        } else {
            h.unit = unit;
            aiMatrix4x4 scaling;
            aiMatrix4x4::Scaling(aiVector3D(static_cast<ai_real>(unit)), scaling);
            collect(*scene, scaling, xyz, h.faces);
            h.vertices = xyz.size() / 3U;
        }
    } catch (const std::exception& e) {
        h.code = kRefused;
        static_cast<void>(std::snprintf(h.message, sizeof(h.message), "the mesh library failed: %s", e.what()));
        xyz.clear();
        h.vertices = 0U;
    }
    return write_answer(fd, h, xyz) ? 0 : 3;
}

[[noreturn]] void run_child(const std::string& path, int fd, const MeshLimits& limits) {
    // A fault dies of its signal, whatever handlers the parent installed (a test runner's, for one).
    for (const int sig : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGXCPU, SIGPIPE}) {
        static_cast<void>(std::signal(sig, SIG_DFL));
    }
    const rlimit memory{limits.memory_bytes, limits.memory_bytes};
    const rlimit cpu{limits.cpu_seconds, limits.cpu_seconds};
    if ((limits.memory_bytes != 0U && ::setrlimit(RLIMIT_AS, &memory) != 0) || ::setrlimit(RLIMIT_CPU, &cpu) != 0) {
        ::_exit(4);
    }
    const MeshChild child = limits.child != nullptr ? limits.child : assimp_child;
    ::_exit(child(path.c_str(), fd));
}

// ---------------------------------------------------------------- the parent

/// Reads the child's answer from @p fd until end of file, at most @p cap
/// bytes, within the deadline; false on a timeout or too much.
bool read_answer(int fd, std::size_t cap, int timeout_ms, std::vector<char>& bytes, bool& timed_out) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    char buffer[65536];
    timed_out = false;
    while (true) {
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline -
                                                                                std::chrono::steady_clock::now());
        pollfd p{fd, POLLIN, 0};
        const int ready = left.count() > 0 ? ::poll(&p, 1, static_cast<int>(left.count())) : 0;
        if (ready < 0 && errno == EINTR) {
            continue;
        }
        if (ready <= 0) {
            timed_out = ready == 0;
            return false;
        }
        const ssize_t n = ::read(fd, buffer, sizeof(buffer));
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            return n == 0;
        }
        if (bytes.size() + static_cast<std::size_t>(n) > cap) {
            return false;
        }
        bytes.insert(bytes.end(), buffer, buffer + n);
    }
}

/// The child's end: its exit status as text ("" when it exited 0).
std::string child_fate(pid_t pid, bool kill_it) {
    if (kill_it) {
        ::kill(pid, SIGKILL);
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (WIFSIGNALED(status)) {
        return std::string("the mesh library's process died of signal ") + std::to_string(WTERMSIG(status)) + " (" +
               strsignal(WTERMSIG(status)) + ")";
    }
    if (WIFEXITED(status) && WEXITSTATUS(status) != 0) {
        return "the mesh library's process exited with status " + std::to_string(WEXITSTATUS(status));
    }
    return "";
}

/// Checks the answer @p bytes and fills @p mesh.
IoStatus decode_answer(const std::vector<char>& bytes, Mesh& mesh) {
    AnswerHeader h;
    if (bytes.size() < sizeof(h)) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "the mesh library's process gave no answer");
    }
    std::memcpy(&h, bytes.data(), sizeof(h));
    h.message[kMessageBytes - 1U] = '\0';
    if (h.magic != kAnswerMagic) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "the mesh library's process gave a malformed answer");
    }
    if (h.code == kRefused) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "%s",
                                 h.message[0] != '\0' ? h.message : "the mesh library refused it");
    }
    if (h.code != kRead || !std::isfinite(h.unit) || !(h.unit > 0.0)) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "the mesh library's process gave a malformed answer");
    }
    if (h.vertices > kMeshMaxVertices) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "more than %zu vertices", kMeshMaxVertices);
    }
    if (bytes.size() != sizeof(h) + h.vertices * 3U * sizeof(double)) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "the mesh library's process gave a truncated answer");
    }
    mesh.vertices.resize(h.vertices);
    for (std::size_t v = 0U; v < h.vertices; ++v) {
        std::memcpy(mesh.vertices[v].data(), bytes.data() + sizeof(h) + v * 3U * sizeof(double), 3U * sizeof(double));
    }
    mesh.faces = h.faces;
    mesh.unit = h.unit;
    return {};
}

/// No vertex, a non-finite one, all in one point or on one line.
IoStatus check_vertices(const Mesh& mesh) {
    if (mesh.vertices.empty()) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "no vertex: an empty mesh");
    }
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (std::size_t v = 0U; v < mesh.vertices.size(); ++v) {
        if (!mesh.vertices[v].allFinite()) {
            return IoStatus::failure(ErrorCode::kNonFiniteValue, "vertex %zu is not finite", v);
        }
        mean += mesh.vertices[v];
    }
    mean /= static_cast<double>(mesh.vertices.size());
    Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
    for (const Eigen::Vector3d& p : mesh.vertices) {
        spread += (p - mean) * (p - mean).transpose();
    }
    const Eigen::Vector3d eigen = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(spread).eigenvalues();
    if (!(eigen[1] > 1e-12 * std::max(eigen[2], 1e-300))) {
        return IoStatus::failure(ErrorCode::kInvalidArgument,
                                 "degenerate: its %zu vertices lie in one point or on one line", mesh.vertices.size());
    }
    return {};
}

IoStatus read_isolated(const std::string& path, Mesh& mesh, const MeshLimits& limits) {
    int fds[2];
    if (::pipe(fds) != 0) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "cannot make a pipe: %s", std::strerror(errno));
    }
    const pid_t pid = ::fork();
    if (pid < 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        return IoStatus::failure(ErrorCode::kInvalidArgument, "cannot fork: %s", std::strerror(errno));
    }
    if (pid == 0) {
        ::close(fds[0]);
        run_child(path, fds[1], limits);
    }
    ::close(fds[1]);
    std::vector<char> bytes;
    bool timed_out = false;
    const bool complete = read_answer(fds[0], sizeof(AnswerHeader) + kMeshMaxVertices * 3U * sizeof(double),
                                      limits.timeout_ms, bytes, timed_out);
    ::close(fds[0]);
    const std::string fate = child_fate(pid, !complete);
    if (timed_out) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "the mesh library took over %d ms: stopped",
                                 limits.timeout_ms);
    }
    if (!fate.empty()) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "%s", fate.c_str());
    }
    if (!complete) {
        return IoStatus::failure(ErrorCode::kMalformedInput, "the mesh library's answer is too large");
    }
    if (const IoStatus st = decode_answer(bytes, mesh); !st) {
        return st;
    }
    return check_vertices(mesh);
}

}  // namespace

bool write_mesh_answer(int fd, const std::vector<double>& vertices, std::size_t faces, double unit) {
    AnswerHeader h;
    h.unit = unit;
    h.faces = faces;
    h.vertices = vertices.size() / 3U;
    return write_answer(fd, h, vertices);
}

IoStatus read_mesh_file(const std::string& path, Mesh& mesh, const MeshLimits& limits) {
    mesh = Mesh{};
    const std::string suffix = lower_suffix(path);
    if (suffix != "stl" && suffix != "dae" && suffix != "obj") {
        return IoStatus::failure(ErrorCode::kUnsupportedType, "%s: only STL, COLLADA (.dae) and OBJ meshes are read",
                                 path.c_str());
    }
    struct stat info {};
    if (::stat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) {
        return IoStatus::failure(ErrorCode::kInvalidArgument, "%s: cannot open", path.c_str());
    }
    if (static_cast<std::size_t>(info.st_size) > kMeshMaxBytes) {
        return IoStatus::failure(ErrorCode::kCapacityExceeded, "%s: %lld bytes, at most %zu", path.c_str(),
                                 static_cast<long long>(info.st_size), kMeshMaxBytes);
    }
    mesh.format = suffix;
    const IoStatus st = read_isolated(path, mesh, limits);
    if (!st) {
        const std::string format = mesh.format;
        mesh = Mesh{};
        mesh.format = format;
        return st.prefixed(path.c_str());
    }
    return {};
}

}  // namespace cellguard::host
