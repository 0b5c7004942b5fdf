// SPDX-FileCopyrightText: 2026 The cellguard authors
// SPDX-License-Identifier: Apache-2.0
// Fuzzes the collision-mesh input (mesh.hpp). The first byte chooses: even, the rest is a mesh file (bit 1..2: .stl,
// .dae, .obj) that the mesh library reads in its child process; odd, the rest is what a child answers through the
// pipe, for the parent's checks. Either way the result is a refusal with a message or finite, non-degenerate
// vertices within the capacity: never a crash of the caller, whatever the mesh library does in its child.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "cellguard/host/io/mesh.hpp"

using namespace cellguard;

namespace {

std::vector<std::uint8_t> g_answer;  // the answer the fake child sends (copied into the child by fork)

int answering_child(const char* /*path*/, int fd) {
    std::size_t done = 0U;
    while (done < g_answer.size()) {
        const ssize_t n = ::write(fd, g_answer.data() + done, g_answer.size() - done);
        if (n <= 0) {
            return 1;
        }
        done += static_cast<std::size_t>(n);
    }
    return 0;
}

void require(bool condition) {
    if (!condition) {
        __builtin_trap();
    }
}

std::string temp_path(const char* suffix) {
    static const std::string dir = [] {
        char pattern[] = "/tmp/cellguard-fuzz-mesh-XXXXXX";
        const char* made = ::mkdtemp(pattern);
        return std::string(made != nullptr ? made : "/tmp");
    }();
    return dir + "/input." + suffix;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1U) {
        return 0;
    }
    const unsigned mode = data[0];
    static const char* const kSuffixes[] = {"stl", "dae", "obj", "STL"};
    const std::string path = temp_path(kSuffixes[(mode >> 1U) & 3U]);
    host::MeshLimits limits;
    limits.memory_bytes = 0U;  // under the sanitizers: see MeshLimits
    limits.cpu_seconds = 2U;
    limits.timeout_ms = 3000;
    if ((mode & 1U) != 0U) {
        g_answer.assign(data + 1, data + size);
        limits.child = answering_child;
        std::FILE* f = std::fopen(path.c_str(), "wb");  // the file must exist; the fake child ignores it
        require(f != nullptr);
        require(std::fclose(f) == 0);
    } else {
        std::FILE* f = std::fopen(path.c_str(), "wb");
        require(f != nullptr);
        require(std::fwrite(data + 1, 1U, size - 1U, f) == size - 1U || size == 1U);
        require(std::fclose(f) == 0);
    }
    host::Mesh mesh;
    const IoStatus st = host::read_mesh_file(path, mesh, limits);
    if (st.ok()) {
        require(!mesh.vertices.empty() && mesh.vertices.size() <= host::kMeshMaxVertices);
        for (const Eigen::Vector3d& v : mesh.vertices) {
            require(v.allFinite());
        }
        require(mesh.unit > 0.0 && std::isfinite(mesh.unit));
    } else {
        require(st.message()[0] != '\0');
        require(mesh.vertices.empty());
    }
    return 0;
}
