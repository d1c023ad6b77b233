// softtouch-cli batch: bake and render a clip library described by a manifest (io/pipeline/batch_plan.h),
// locally in parallel or as a Slurm job array. docs/farm.md.
#include "app/cli_commands.h"
#include "app/cli_options.h"
#include "app/cli_support.h"

#include "io/documents/preset_file.h"
#include "io/documents/project_file.h"
#include "io/export/export_formats.h"
#include "io/export/lattice_cache.h"
#include "io/export/vertex_cache.h"
#include "io/export/video_encoder.h"
#include "io/files/atomic_file.h"
#include "io/files/input_file.h"
#include "io/import/mesh_import.h"
#include "io/pipeline/bake.h"
#include "io/pipeline/batch_plan.h"
#include "render/video_render.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <csignal>
#include <mutex>
#include <thread>

#include <fcntl.h>
#include <sys/prctl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace softtouch::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kBatchAbout = R"(A clip library as a manifest (docs/farm.md): scenes x material presets x clips x formats, one job per
output, each with a stable id and a hash of everything it reads; a job whose stamp holds its current
hash is up to date and skipped.

  plan MANIFEST                 List the jobs: id, up to date or to run, output.
  run MANIFEST [--jobs N]       Run every job that is not up to date, N at a time (default: the cores),
                                each in its own process; a progress line, then a summary with each
                                failure's reason. Exit 1 if any job failed.
  run MANIFEST --job ID         Run exactly one job (what a farm task calls).
  slurm MANIFEST --out DIR      Write DIR/softtouch-batch.sbatch (one array task per job to run, the
                                manifest's resources, a log per task in DIR/logs/), DIR/jobs.txt and
                                DIR/collect.sh (checks the library once the array is done).
  check MANIFEST                Every job's outputs exist, match its stamp and read back.
)";

/// Set in a job's environment by the local batch that started it: that batch's pid.
constexpr const char* kBatchParentVariable = "SOFTTOUCH_BATCH_PARENT";

/// Runs one job in this process: load, apply the preset, bake or render, stamp. Returns the files written.
Result<std::vector<fs::path>> runJob(const io::BatchManifest& manifest, const io::BatchJob& job) {
    auto project = io::loadProjectToRun(job.scene);
    if (!project)
        return Status::error(project.message());
    if (!job.preset.empty()) {
        auto preset = io::loadMaterialPreset(job.preset);
        if (!preset)
            return Status::error(preset.message());
        for (SceneObject& object : project->scene.objects)
            if (Status s = io::applyMaterialPreset(preset.value(), object.lattice, object.material); !s)
                return Status::error("preset '" + job.preset.string() + "' on " + object.name + ": " + s.message());
    }
    std::error_code ec;
    fs::create_directories(job.output.parent_path(), ec);
    if (ec)
        return Status::error("cannot create '" + job.output.parent_path().string() + "': " + ec.message());
    std::vector<fs::path> files;
    if (io::isVideoFormat(job.format)) {
        render::VideoRenderOptions options;
        options.video.output = job.output;
        options.video.format = io::videoFormatFromPath(job.output).value();
        options.video.width = job.videoWidth;
        options.video.height = job.videoHeight;
        options.frames.clips = &project->clips;
        options.frames.clip = job.clip;
        options.frames.frames = job.frames;
        auto rendered = render::renderVideo(project->scene, options);
        if (!rendered)
            return Status::error(rendered.message());
        files.push_back(job.output);
    } else {
        io::BakeOptions options;
        options.output = job.output;
        const io::ExportFormat& format = *io::findExportFormat(job.format);  // the manifest reader checked the name
        options.format = &format;
        io::ExportSettings settings;
        settings.compress = job.compress;  // the plan set it only for a format that takes it
        options.exportOptions = io::exportOptions(format, settings).value();
        options.frames = job.frames;
        options.clips = &project->clips;
        options.clip = job.clip;
        options.meshSources = io::meshSources(project.value());
        options.threads = manifest.resources.cpusPerTask;
        auto baked = io::bake(project->scene, options);
        if (!baked)
            return Status::error(baked.message());
        files = baked->files;
        files.push_back(baked->restMesh);
    }
    std::sort(files.begin(), files.end());
    files.erase(std::unique(files.begin(), files.end()), files.end());
    if (Status s = io::writeBatchStamp(manifest, job, files); !s)
        return Status::error(s.message());
    return files;
}

/// What a finished child process said: exit status and everything it printed.
struct ChildResult {
    int exitCode = -1;
    std::string output;
};

/// Runs `softtouch-cli batch run MANIFEST --job ID [--force]` as a child process of this binary, so a job
/// that crashes or is killed takes only itself down, and reads what it prints.
ChildResult runChild(const io::BatchJob& job, const io::BatchManifest& manifest, bool force) {
    ChildResult result;
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    int pipeFds[2];
    if (ec || ::pipe2(pipeFds, O_CLOEXEC) != 0) {
        result.output = "cannot start a job process";
        return result;
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, pipeFds[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, pipeFds[1], STDERR_FILENO);
    std::vector<std::string> args = {self.string(), "batch",     "run",
                                     manifest.path.string(), "--job", job.id,
                                     "--library", manifest.outputRoot.string()};
    if (force)
        args.push_back("--force");
    std::vector<char*> argv;
    for (std::string& a : args)
        argv.push_back(a.data());
    argv.push_back(nullptr);
    // The environment, plus who started the job (it stops when this process ends).
    std::string parent = std::string(kBatchParentVariable) + "=" + std::to_string(::getpid());
    std::vector<char*> envp;
    for (char** e = environ; *e != nullptr; ++e)
        if (std::strncmp(*e, kBatchParentVariable, std::strlen(kBatchParentVariable)) != 0)
            envp.push_back(*e);
    envp.push_back(parent.data());
    envp.push_back(nullptr);
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, self.c_str(), &actions, nullptr, argv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    ::close(pipeFds[1]);
    if (spawned != 0) {
        ::close(pipeFds[0]);
        result.output = std::string("cannot start a job process: ") + std::strerror(spawned);
        return result;
    }
    io::stopChildProcessOnSignal(pid);  // a Ctrl+C, SIGTERM or SIGHUP of the batch stops the job too
    char buffer[4096];
    for (ssize_t n; (n = ::read(pipeFds[0], buffer, sizeof buffer)) != 0;) {
        if (n < 0 && errno == EINTR)
            continue;
        if (n < 0)
            break;
        result.output.append(buffer, std::size_t(n));
    }
    ::close(pipeFds[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    io::forgetChildProcess(pid);
    result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    if (WIFSIGNALED(status))
        result.output += "\nthe job's process ended by signal " + std::to_string(WTERMSIG(status));
    return result;
}

/// The last line of a child's output that says what went wrong (or its last line).
std::string reasonOf(const std::string& output) {
    std::string reason;
    std::size_t start = 0;
    while (start < output.size()) {
        std::size_t end = output.find('\n', start);
        if (end == std::string::npos)
            end = output.size();
        const std::string line = output.substr(start, end - start);
        if (!line.empty() && (reason.empty() || line.find("error") != std::string::npos || line.find("signal") != std::string::npos))
            reason = line;
        start = end + 1;
    }
    const std::string prefix = "softtouch-cli: error: ";
    return reason.rfind(prefix, 0) == 0 ? reason.substr(prefix.size()) : reason;
}

int runLocal(const io::BatchManifest& manifest, const std::vector<io::BatchJob>& jobs, int parallel, bool force,
             bool quiet) {
    std::vector<const io::BatchJob*> todo;
    for (const io::BatchJob& job : jobs)
        if (force || !io::batchJobUpToDate(manifest, job))
            todo.push_back(&job);
    const std::size_t skipped = jobs.size() - todo.size();
    std::vector<ChildResult> results(todo.size());
    std::atomic<std::size_t> next{0}, done{0};
    std::mutex printing;
    const auto start = std::chrono::steady_clock::now();
    auto progress = [&] {
        if (quiet)
            return;
        const std::size_t d = done.load(), width = 30, filled = todo.empty() ? width : width * d / todo.size();
        std::fprintf(stderr, "\r[%s%s] %zu/%zu jobs run, %zu up to date, %.0f s", std::string(filled, '#').c_str(),
                     std::string(width - filled, '.').c_str(), d, todo.size(), skipped,
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        std::fflush(stderr);
    };
    auto work = [&] {
        for (std::size_t i = next++; i < todo.size(); i = next++) {
            results[i] = runChild(*todo[i], manifest, force);
            ++done;
            std::lock_guard lock(printing);
            progress();
        }
    };
    progress();
    {
        std::vector<std::jthread> workers;
        for (int t = 0; t < std::min<int>(parallel, int(todo.size())); ++t)
            workers.emplace_back(work);
    }
    if (!quiet)
        std::fputc('\n', stderr);
    std::size_t failed = 0;
    for (std::size_t i = 0; i < todo.size(); ++i)
        if (results[i].exitCode != 0) {
            ++failed;
            std::fprintf(stderr, "softtouch-cli: job %s failed: %s\n", todo[i]->id.c_str(), reasonOf(results[i].output).c_str());
        }
    std::printf("%zu jobs: %zu ran, %zu up to date, %zu failed; library in %s\n", jobs.size(), todo.size() - failed,
                skipped, failed, manifest.outputRoot.string().c_str());
    return failed == 0 ? 0 : 1;
}

/// Single-quoted for a POSIX shell.
std::string shellQuoted(const std::string& text) {
    std::string quoted = "'";
    for (char c : text)
        quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return quoted + "'";
}

int writeSlurm(const io::BatchManifest& manifest, const std::vector<io::BatchJob>& jobs, const fs::path& dir, bool all) {
    std::vector<const io::BatchJob*> todo;
    for (const io::BatchJob& job : jobs)
        if (all || !io::batchJobUpToDate(manifest, job))
            todo.push_back(&job);
    std::error_code ec;
    fs::create_directories(dir / "logs", ec);
    if (ec)
        return fail("cannot create '" + (dir / "logs").string() + "': " + ec.message());
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    if (ec)
        return fail("cannot find this program's path: " + ec.message());
    const fs::path absDir = fs::absolute(dir).lexically_normal();
    // Every path below goes into a script a shell runs and sbatch parses line by line: values are
    // single-quoted for the shell, and a control character (a newline would start a command of its
    // own) is refused outright, since no quoting survives sbatch's #SBATCH lines.
    for (const auto& [what, path] : {std::pair<const char*, fs::path>{"the manifest's path", manifest.path},
                                     {"--out", absDir},
                                     {"the library's path", manifest.outputRoot},
                                     {"this program's path", self}})
        if (io::hasControlCharacter(path.string()))
            return fail(std::string("batch slurm: ") + what + " '" + io::shownName(path.string()) +
                        "' holds a control character (a newline, a tab, ...), which would break the script: rename it");
    std::string list;
    for (const io::BatchJob* job : todo)
        list += job->id + "\n";
    if (Status s = io::writeFileAtomically(dir / "jobs.txt", list); !s)
        return fail(s.message());
    const std::string cli = shellQuoted(self.string()), manifestPath = shellQuoted(manifest.path.string()),
                      library = shellQuoted(manifest.outputRoot.string());
    const io::BatchResources& r = manifest.resources;
    std::string script = "#!/bin/bash\n"
                         "# Written by softtouch-cli batch slurm: one array task per job of jobs.txt.\n"
                         "# Submit: sbatch " + (absDir / "softtouch-batch.sbatch").string() + "\n"
                         "#SBATCH --job-name=softtouch-" + io::libraryName(manifest.path.stem().string()) + "\n";
    if (!todo.empty())
        script += "#SBATCH --array=0-" + std::to_string(todo.size() - 1) + "\n";
    script += "#SBATCH --cpus-per-task=" + std::to_string(r.cpusPerTask) + "\n"
              "#SBATCH --mem=" + std::to_string(r.memoryMB) + "M\n"
              "#SBATCH --time=" + std::to_string(r.minutes) + "\n"
              "#SBATCH --output=" + (absDir / "logs" / "%A_%a.out").string() + "\n";
    if (!r.partition.empty())
        script += "#SBATCH --partition=" + r.partition + "\n";
    // With nothing to run the script has no array and Slurm sets no task id: it says so and succeeds, so
    // a nightly `batch slurm ... && sbatch ...` does not fail on the nights nothing changed.
    script += "set -euo pipefail\n"
              "if [ ! -s " + shellQuoted((absDir / "jobs.txt").string()) + " ]; then\n"
              "  echo 'softtouch batch: every job is up to date; nothing to run'\n"
              "  exit 0\n"
              "fi\n"
              "id=$(sed -n \"$((SLURM_ARRAY_TASK_ID + 1))p\" " + shellQuoted((absDir / "jobs.txt").string()) + ")\n"
              "exec " + cli + " batch run " + manifestPath + " --library " + library + " --job \"$id\"\n";
    const std::string collect = "#!/bin/bash\n"
                                "# Written by softtouch-cli batch slurm: run after the array has finished.\n"
                                "exec " + cli + " batch check " + manifestPath + " --library " + library + "\n";
    if (Status s = io::writeFileAtomically(dir / "softtouch-batch.sbatch", script); !s)
        return fail(s.message());
    if (Status s = io::writeFileAtomically(dir / "collect.sh", collect); !s)
        return fail(s.message());
    fs::permissions(dir / "collect.sh", fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                    fs::perm_options::add, ec);
    if (todo.empty())
        std::printf("every one of the %zu jobs is up to date: the script has no array (--force lists them all)\n",
                    jobs.size());
    else
        std::printf("%zu of %zu jobs to run\nsubmit:  sbatch %s\nthen:    %s\n", todo.size(), jobs.size(),
                    (absDir / "softtouch-batch.sbatch").string().c_str(), (absDir / "collect.sh").string().c_str());
    return 0;
}

/// Reads an output back the way a pipeline would; empty when it reads. Meshes (an OBJ sequence's hundreds of
/// frames) go to assimp together, in as few importer children as it takes.
std::string readBack(const io::BatchJob& job, const std::vector<fs::path>& files) {
    std::vector<fs::path> meshes;
    for (const fs::path& file : files)
        if (const std::string ext = file.extension().string(); ext == ".obj" || ext == ".glb" || ext == ".gltf")
            meshes.push_back(file);
    if (Status s = io::checkMeshesImport(meshes); !s)
        return "job " + job.id + ": " + s.message();
    for (const fs::path& file : files) {
        const std::string ext = file.extension().string();
        std::string message;
        if (ext == ".pc2")
            message = io::readPc2(file).message();
        else if (ext == ".mdd")
            message = io::readMdd(file).message();
        else if (file.filename().string().ends_with(".lattice.bin"))
            message = io::readLatticeCache(file).message();
        else if (ext == ".mp4" || ext == ".gif")
            message = io::probeVideo(file).message();
        if (!message.empty())
            return "job " + job.id + ": " + message;
    }
    return {};
}

int check(const io::BatchManifest& manifest, const std::vector<io::BatchJob>& jobs) {
    std::size_t bad = 0;
    for (const io::BatchJob& job : jobs) {
        const auto files = io::batchStampFiles(manifest, job);
        std::string problem;
        if (!files)
            problem = "job " + job.id + ": not done (no stamp for its current inputs, or a file it wrote is missing or changed)";
        else
            problem = readBack(job, *files);
        if (!problem.empty()) {
            ++bad;
            std::fprintf(stderr, "softtouch-cli: %s\n", problem.c_str());
        }
    }
    std::printf("%zu of %zu jobs done and readable\n", jobs.size() - bad, jobs.size());
    return bad == 0 ? 0 : 1;
}

}  // namespace

int runBatch(const std::vector<std::string>& args) {
    std::string action, manifestPath, jobId, outDir, library;
    std::optional<double> parallel;
    bool force = false, quiet = false;
    CommandLine line("batch", kBatchAbout);
    line.positional("ACTION", action, {"plan|run|slurm|check", "", true});
    line.positional("MANIFEST", manifestPath, "The library's manifest (*.stbatch).");
    line.number("--jobs", parallel, {1, 256, true}, {"N", "run: jobs at a time (default: the cores)."});
    line.text("--job", jobId, {"ID", "run: exactly this job."});
    line.text("--out", outDir, {"DIR", "slurm: where the job array's script, job list and collect script go."});
    line.text("--library", library, {"DIR", "Where the library goes (default: the manifest's outputRoot, else library/ beside it)."});
    line.flag("--force", force, "Run jobs even when up to date (run), list every job (slurm).");
    line.flag("--quiet", quiet, "No progress line (plan, run).");
    if (const auto exit = line.parse(args))
        return *exit;
    if (action != "plan" && action != "run" && action != "slurm" && action != "check")
        return line.usage("unknown batch action '" + action + "' (expected plan, run, slurm or check)");
    if (action == "slurm" && outDir.empty())
        return line.usage("batch slurm needs --out DIR");
    if ((!jobId.empty() || parallel) && action != "run")
        return line.usage("--job and --jobs are for batch run");
    if (!jobId.empty() && parallel)
        return line.usage("--job runs one job; --jobs is for the whole library");

    auto loaded = io::loadBatchManifest(manifestPath);
    if (!loaded)
        return fail(loaded.message());
    io::BatchManifest manifest = loaded.value();
    if (!library.empty())
        manifest.outputRoot = fs::absolute(library).lexically_normal();
    // A large product takes a while to plan (every scene is loaded, every input hashed): say how far it is.
    const auto planStart = std::chrono::steady_clock::now();
    bool planShown = false;
    auto planProgress = [&](std::size_t planned, std::size_t total) {
        if (quiet || (!planShown && std::chrono::steady_clock::now() - planStart < std::chrono::seconds(1)))
            return;
        planShown = true;
        std::fprintf(stderr, "\rplanning: %zu of %zu jobs", planned, total);
        std::fflush(stderr);
    };
    auto planned = io::planBatch(manifest, planProgress);
    if (planShown)
        std::fputc('\n', stderr);
    if (!planned)
        return fail(planned.message());
    const std::vector<io::BatchJob>& jobs = planned.value();

    if (action == "plan") {
        std::size_t upToDate = 0;
        for (const io::BatchJob& job : jobs) {
            const bool current = io::batchJobUpToDate(manifest, job);
            upToDate += current;
            std::printf("%-48s %-10s %s %s\n", job.id.c_str(), current ? "up-to-date" : "to-run",
                        io::hashText(job.hash).c_str(), job.output.lexically_relative(manifest.outputRoot).string().c_str());
        }
        std::printf("%zu jobs, %zu up to date, %zu to run; library in %s\n", jobs.size(), upToDate,
                    jobs.size() - upToDate, manifest.outputRoot.string().c_str());
        return 0;
    }
    if (action == "check")
        return check(manifest, jobs);
    if (action == "slurm")
        return writeSlurm(manifest, jobs, outDir, force);
    if (!jobId.empty()) {
        const auto it = std::find_if(jobs.begin(), jobs.end(), [&](const io::BatchJob& j) { return j.id == jobId; });
        if (it == jobs.end())
            return fail("no job '" + jobId + "' in " + manifest.path.string() + " ('softtouch-cli batch plan' lists them)");
        // A job a local batch started ends with that batch, whatever ended it (kill -9 included):
        // nothing is published after the batch has returned. (A job started any other way, by a
        // farm or by hand under nohup, runs on its own.)
        if (const char* parent = std::getenv(kBatchParentVariable)) {
            ::prctl(PR_SET_PDEATHSIG, SIGTERM);
            if (std::to_string(::getppid()) != parent)  // the batch was already gone before the line above
                return fail("job " + it->id + ": the batch that started it has ended");
        }
        if (!force && io::batchJobUpToDate(manifest, *it)) {
            std::printf("%s: up to date\n", it->id.c_str());
            return 0;
        }
        auto files = runJob(manifest, *it);
        if (!files)
            return fail("job " + it->id + ": " + files.message());
        printWritten(files.value());
        return 0;
    }
    const int threads = parallel ? int(*parallel) : std::max(1u, std::thread::hardware_concurrency());
    return runLocal(manifest, jobs, threads, force, quiet);
}

}  // namespace softtouch::cli
