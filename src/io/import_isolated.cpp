// Importing in a child process, so that a crash in a third-party parser becomes an error.
// assimp 5.2 (Debian 12's) reads 40-odd formats with parsers of uneven hardening: it dies with
// SIGSEGV on files its own exporter writes (an ASCII FBX of the bundled box), and a batch of ten
// thousand assets must not stop at the first such file. The same technique as browsers' and
// thumbnailers' out-of-process decoders:
//  1. fork(); the child runs import_mesh in process and streams the Result (a status, or the mesh
//     and the import report) through a pipe, field by field, then _exit()s without running the
//     parent's atexit handlers;
//  2. the parent reads the stream into a Mesh as it arrives (no second copy of a large mesh), then
//     waits for the child: a child killed by a signal, or one that ends before its result is whole,
//     is reported as one line naming the file and what to do.
// POSIX only (fork, pipe, waitpid): standin targets Debian. Embedders opt in through
// ImportOptions::isolate_parser; the command line and the viewer always do.
#include <standin/files.h>
#include <standin/mesh.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

namespace standin {

namespace {

constexpr std::uint32_t k_stream_magic = 0x49534d53; // "SMSI": standin mesh stream, isolated import

// ---- the child's side: write everything, give up quietly when the parent has gone --------------

class StreamWriter {
public:
    explicit StreamWriter(int fd) : fd_(fd) {}
    bool ok() const { return ok_; }

    void bytes(const void* data, std::size_t size)
    {
        const char* p = static_cast<const char*>(data);
        while (ok_ && size > 0) {
            ssize_t n = ::write(fd_, p, size);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                ok_ = false;
                return;
            }
            p += n;
            size -= std::size_t(n);
        }
    }
    template <typename T> void value(const T& v)
    {
        static_assert(std::is_trivially_copyable_v<T>);
        bytes(&v, sizeof v);
    }
    void text(const std::string& s)
    {
        value(std::uint64_t(s.size()));
        bytes(s.data(), s.size());
    }
    template <typename T> void array(const std::vector<T>& v)
    {
        static_assert(std::is_trivially_copyable_v<T>);
        value(std::uint64_t(v.size()));
        bytes(v.data(), v.size() * sizeof(T));
    }

private:
    int fd_;
    bool ok_ = true;
};

// ---- the parent's side: read what arrives, notice an early end -------------------------------

class StreamReader {
public:
    explicit StreamReader(int fd) : fd_(fd) {}
    bool ok() const { return ok_; }

    void bytes(void* data, std::size_t size)
    {
        char* p = static_cast<char*>(data);
        while (ok_ && size > 0) {
            ssize_t n = ::read(fd_, p, size);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) {
                ok_ = false;
                return;
            }
            p += n;
            size -= std::size_t(n);
        }
    }
    template <typename T> T value()
    {
        T v{};
        bytes(&v, sizeof v);
        return v;
    }
    // Counts come from our own child, but a child that died mid-write leaves garbage only at the
    // end of the stream (which reads as an early end), never a wrong count: still bounded, so that
    // a logic error cannot turn into a huge allocation.
    std::size_t count(std::size_t element_size)
    {
        std::uint64_t n = value<std::uint64_t>();
        if (!ok_ || n > (std::uint64_t(1) << 40) / element_size) {
            ok_ = false;
            return 0;
        }
        return std::size_t(n);
    }
    std::string text()
    {
        std::string s(count(1), '\0');
        bytes(s.data(), s.size());
        return s;
    }
    template <typename T> void array(std::vector<T>& v)
    {
        v.resize(count(sizeof(T)));
        bytes(v.data(), v.size() * sizeof(T));
    }

private:
    int fd_;
    bool ok_ = true;
};

// Material fields one by one (its name is a string), so the stream does not depend on padding.
void write_material(StreamWriter& w, const Material& m)
{
    w.text(m.name);
    w.value(m.base_color);
    w.value(m.base_color_texture);
    w.value(m.alpha_mode);
    w.value(m.alpha_cutoff);
    w.value(m.double_sided);
    w.value(m.metallic);
    w.value(m.roughness);
    w.value(m.emissive);
    w.value(m.occlusion_strength);
    w.value(m.normal_scale);
    w.value(m.metallic_roughness_texture);
    w.value(m.occlusion_texture);
    w.value(m.emissive_texture);
    w.value(m.normal_texture);
}

Material read_material(StreamReader& r)
{
    Material m;
    m.name = r.text();
    m.base_color = r.value<glm::vec4>();
    m.base_color_texture = r.value<int>();
    m.alpha_mode = r.value<AlphaMode>();
    m.alpha_cutoff = r.value<float>();
    m.double_sided = r.value<bool>();
    m.metallic = r.value<float>();
    m.roughness = r.value<float>();
    m.emissive = r.value<glm::vec3>();
    m.occlusion_strength = r.value<float>();
    m.normal_scale = r.value<float>();
    m.metallic_roughness_texture = r.value<int>();
    m.occlusion_texture = r.value<int>();
    m.emissive_texture = r.value<int>();
    m.normal_texture = r.value<int>();
    return m;
}

void write_result(StreamWriter& w, const Result<Mesh>& result, const ImportReport& report)
{
    w.value(k_stream_magic);
    w.value(std::int32_t(result.status().code()));
    w.text(result.status().message());
    w.text(report.format);
    w.value(std::uint64_t(report.degenerate_dropped));
    w.value(std::uint64_t(report.meshes_in_scene));
    w.value(std::uint64_t(report.warnings.size()));
    for (const std::string& warning : report.warnings) w.text(warning);
    if (!result.is_ok()) return;
    const Mesh& mesh = *result;
    w.array(mesh.positions);
    w.array(mesh.normals);
    w.array(mesh.colors);
    w.array(mesh.uvs);
    w.array(mesh.indices);
    w.array(mesh.face_materials);
    w.value(std::uint64_t(mesh.materials.size()));
    for (const Material& m : mesh.materials) write_material(w, m);
    w.value(std::uint64_t(mesh.textures.size()));
    for (const Texture& t : mesh.textures) {
        w.text(t.name);
        w.value(t.width);
        w.value(t.height);
        w.array(t.rgba);
    }
    w.value(k_stream_magic); // the end: a stream without it was cut short
}

// Reads the child's stream; `complete` says whether it arrived whole (else the result means nothing).
Result<Mesh> read_result(StreamReader& r, ImportReport& report, bool& complete)
{
    complete = false;
    const Status cut_short = error(StatusCode::bad_data, "cut short"); // replaced by the caller
    if (r.value<std::uint32_t>() != k_stream_magic || !r.ok()) return cut_short;
    auto code = StatusCode(r.value<std::int32_t>());
    std::string message = r.text();
    report.format = r.text();
    report.degenerate_dropped = std::size_t(r.value<std::uint64_t>());
    report.meshes_in_scene = std::size_t(r.value<std::uint64_t>());
    report.warnings.resize(r.count(sizeof(std::string)));
    for (std::string& warning : report.warnings) warning = r.text();
    if (!r.ok()) return cut_short;
    if (code != StatusCode::ok) {
        complete = true;
        return error(code, message);
    }
    Mesh mesh;
    r.array(mesh.positions);
    r.array(mesh.normals);
    r.array(mesh.colors);
    r.array(mesh.uvs);
    r.array(mesh.indices);
    r.array(mesh.face_materials);
    mesh.materials.resize(r.count(sizeof(Material)));
    for (Material& m : mesh.materials) m = read_material(r);
    mesh.textures.resize(r.count(sizeof(Texture)));
    for (Texture& t : mesh.textures) {
        t.name = r.text();
        t.width = r.value<int>();
        t.height = r.value<int>();
        r.array(t.rgba);
    }
    complete = r.value<std::uint32_t>() == k_stream_magic && r.ok();
    return mesh;
}

std::string signal_name(int signal)
{
    const char* description = strsignal(signal);
    return "signal " + std::to_string(signal) + (description ? std::string(", ") + description : std::string());
}

} // namespace

Result<Mesh> import_mesh_isolated(const std::string& path, ImportReport& report, const ImportOptions& options)
{
    int fds[2];
    if (::pipe(fds) != 0)
        return error(StatusCode::io_error, quoted(path) + ": cannot start the importer: pipe: " + std::strerror(errno));
    pid_t child = ::fork();
    if (child < 0) {
        int e = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        return error(StatusCode::io_error, quoted(path) + ": cannot start the importer: fork: " + std::strerror(e));
    }
    if (child == 0) {
        ::close(fds[0]);
        ::signal(SIGPIPE, SIG_IGN); // a parent that stopped reading ends the writes, not the child
        ImportOptions in_process = options;
        in_process.isolate_parser = false;
        ImportReport child_report;
        Result<Mesh> result = import_mesh(path, &child_report, in_process);
        StreamWriter writer(fds[1]);
        write_result(writer, result, child_report);
        ::close(fds[1]);
        ::_exit(writer.ok() ? 0 : 1);
    }

    ::close(fds[1]);
    StreamReader reader(fds[0]);
    bool complete = false;
    Result<Mesh> result = read_result(reader, report, complete);
    ::close(fds[0]);
    int wait_status = 0;
    while (::waitpid(child, &wait_status, 0) < 0 && errno == EINTR) {
    }
    const std::string advice = ": the file is damaged or uses a feature the importer mishandles; re-export it, "
                               "preferably as glTF (.glb) or OBJ";
    if (WIFSIGNALED(wait_status))
        return error(StatusCode::bad_data, quoted(path) + ": the model importer (assimp) crashed reading it (" +
                                               signal_name(WTERMSIG(wait_status)) + ")" + advice);
    if (!complete) // e.g. a crash a sanitizer caught and turned into an exit status
        return error(StatusCode::bad_data, quoted(path) + ": the model importer (assimp) ended without a result (exit status " +
                                               std::to_string(WIFEXITED(wait_status) ? WEXITSTATUS(wait_status) : -1) +
                                               ")" + advice);
    return result;
}

} // namespace standin
