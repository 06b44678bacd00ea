#pragma once
// A throwaway PostgreSQL cluster for tests: initdb + pg_ctl on a Unix socket in a temporary
// directory, no TCP, started once per test program (about a second) and removed at exit. initdb
// refuses to run as root, and CI runs as root: then the server runs as `nobody`, started from a
// forked child that drops its privileges. Skips (with a reason) when PostgreSQL's server
// binaries are not installed. Thread affinity: test main thread.

#include <glob.h>
#include <pwd.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <libpq-fe.h>

namespace vx::world::test {

class PgCluster {
public:
    // The process-wide cluster, started on first use; null (and `why` set) when it cannot run.
    static PgCluster* get(std::string* why = nullptr) {
        static std::unique_ptr<PgCluster> cluster;
        static std::string reason;
        static bool tried = false;
        if (!tried) {
            tried = true;
            auto c = std::unique_ptr<PgCluster>(new PgCluster());
            reason = c->init();
            if (reason.empty())
                cluster = std::move(c);
        }
        if (why)
            *why = reason;
        return cluster.get();
    }

    ~PgCluster() {
        if (m_running)
            run_as_owner({m_bin + "/pg_ctl", "-D", m_dir + "/data", "-m", "immediate", "-w", "stop"});
        std::error_code ec;
        std::filesystem::remove_all(m_dir, ec);
    }

    // A new, empty database; its URI.
    std::string new_database() { return create_database(next_database_name()); }
    // A name no database of this cluster has yet (for a database made later: create_database).
    std::string next_database_name() { return "vxtest_" + std::to_string(++m_databases); }
    // Creates database `name`; its URI.
    std::string create_database(const std::string& name) {
        const std::string sql = "CREATE DATABASE " + name;
        PGconn* c = PQconnectdb(uri("postgres").c_str());
        PQclear(PQexec(c, sql.c_str()));
        PQfinish(c);
        return uri(name);
    }
    std::string uri(const std::string& db) const {
        return "postgresql:///" + db + "?host=" + m_dir + "&user=vx";
    }
    // Stops the server (fast shutdown: connections are cut) and starts it again.
    bool stop() {
        m_running = !run_as_owner({m_bin + "/pg_ctl", "-D", m_dir + "/data", "-m", "fast", "-w", "stop"});
        return !m_running;
    }
    bool start() {
        m_running = run_as_owner({m_bin + "/pg_ctl", "-D", m_dir + "/data", "-l", m_dir + "/log", "-w", "-o",
                                  "-k " + m_dir + " -c listen_addresses= -c fsync=on", "start"});
        return m_running;
    }
    const std::string& dir() const { return m_dir; }

private:
    PgCluster() = default;

    std::string init() {
        const char* env = std::getenv("VX_PG_BINDIR");
        if (env && *env) {
            m_bin = env;
        } else {
            glob_t g{};
            if (::glob("/usr/lib/postgresql/*/bin/initdb", 0, nullptr, &g) == 0 && g.gl_pathc > 0)
                m_bin = std::filesystem::path(g.gl_pathv[g.gl_pathc - 1]).parent_path();
            globfree(&g);
        }
        if (m_bin.empty() || !std::filesystem::exists(m_bin + "/initdb"))
            return "PostgreSQL server binaries not found (apt-get install postgresql, or set VX_PG_BINDIR)";
        char tmpl[] = "/tmp/vxpg_XXXXXX";
        if (!mkdtemp(tmpl))
            return "cannot make a temporary directory";
        m_dir = tmpl;
        if (geteuid() == 0) {
            const passwd* pw = getpwnam("nobody");
            if (!pw)
                return "running as root and there is no user 'nobody' to run PostgreSQL as";
            m_uid = pw->pw_uid;
            m_gid = pw->pw_gid;
            if (chown(m_dir.c_str(), m_uid, m_gid) != 0)
                return "cannot hand the cluster directory to 'nobody'";
        }
        chmod(m_dir.c_str(), 0777); // The socket lives here; clients of any user connect.
        if (!run_as_owner({m_bin + "/initdb", "-D", m_dir + "/data", "-A", "trust", "-U", "vx", "--no-sync",
                           "-E", "UTF8", "--locale=C"}))
            return "initdb failed (see " + m_dir + ")";
        if (!start())
            return "pg_ctl start failed (log: " + m_dir + "/log)";
        return {};
    }

    // Runs a program as the cluster's owner (nobody when we are root), output discarded.
    bool run_as_owner(const std::vector<std::string>& args) const {
        const pid_t pid = fork();
        if (pid == 0) {
            if (geteuid() == 0 && (setgid(m_gid) != 0 || setuid(m_uid) != 0))
                _exit(126);
            if (!std::freopen("/dev/null", "w", stdout) || !std::freopen("/dev/null", "w", stderr))
                _exit(126);
            std::vector<char*> argv;
            for (const std::string& a : args)
                argv.push_back(const_cast<char*>(a.c_str()));
            argv.push_back(nullptr);
            execv(argv[0], argv.data());
            _exit(127);
        }
        int status = 0;
        waitpid(pid, &status, 0);
        return WIFEXITED(status) && WEXITSTATUS(status) == 0;
    }

    std::string m_bin, m_dir;
    uid_t m_uid = 0;
    gid_t m_gid = 0;
    bool m_running = false;
    int m_databases = 0;
};

} // namespace vx::world::test
