// ogf-map-query: asks the running ogf-mapper about its map (OGF_MAP_QUERY) or orders it (OGF_MAP_COMMAND)
// and prints the reply, the command-line face of the map services a planner uses over LCM.
//   ogf-map-query cell X Y Z [X Y Z ...]          probability, class, mean, variance, entropy per point
//   ogf-map-query box XMIN YMIN ZMIN XMAX YMAX ZMAX  known and unknown volume, mean entropy of the box
//   ogf-map-query --key FILE save | reset | export FORMAT NAME   (signed with the mapper's key)
//   ogf-map-query keygen FILE                      a new key file (mode 0600) for services.key_file
//   ogf-map-query sources [--json]                 each source of scans the mapper's status lists: robot,
//                                                  sensor, channels, state, counts, last position, trail
// Exit 0 when answered (or done), 1 when refused, failed or unanswered within --timeout, 2 on bad usage.
#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>
#include <unistd.h>

#include <ogf/map_command_reply_t.hpp>
#include <ogf/map_command_t.hpp>
#include <ogf/map_query_reply_t.hpp>
#include <ogf/map_query_t.hpp>
#include <ogf/mapper_status_t.hpp>

#include <chrono>
#include <cstdio>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "ogf/common/command_line.hpp"
#include "ogf/common/json_string.hpp"
#include "ogf/messages/source_status_names.hpp"
#include "ogf/mapper_daemon/command_auth.hpp"
#include "ogf/transport/lcm_asio_bridge.hpp"
#include "ogf/transport/lcm_url.hpp"
#include "ogf/transport/logging.hpp"
#include "ogf/transport/subscriber.hpp"

namespace {

constexpr int kExitOk = 0, kExitFailed = 1, kExitUsage = 2;
using ogf::messages::clocksName;
using ogf::messages::inputsName;
using ogf::messages::scansDropped;

std::int64_t nowUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// One line per source: who it is, where its scans and poses come from, its state, its counts and where its
// sensor was last (map frame, metres; "-" before its first mapped scan).
void printSources(const ogf::mapper_status_t& m) {
  std::printf("%zu sources (mapper status at utime %lld)\n", m.sources.size(), static_cast<long long>(m.utime));
  std::printf("%-12s %-12s %-24s %-7s %-14s %-17s %-8s %8s %8s %8s %8s %8s %26s %5s\n", "robot", "sensor", "channel",
              "kind", "pose_channel", "inputs", "clocks", "scans_in", "mapped", "dropped", "rejected", "poses_in",
              "last_position", "trail");
  for (const auto& s : m.sources) {
    char last[64] = "-";
    if (!s.trail.empty()) {
      const auto& p = s.trail.back();
      std::snprintf(last, sizeof last, "%.2f,%.2f,%.2f", static_cast<double>(p[0]), static_cast<double>(p[1]),
                    static_cast<double>(p[2]));
    }
    std::printf("%-12s %-12s %-24s %-7s %-14s %-17s %-8s %8lld %8lld %8lld %8lld %8lld %26s %5zu\n", s.robot.c_str(),
                s.name.c_str(), s.scan_channel.c_str(), s.packets ? "packets" : "scans",
                s.pose_channel.empty() ? "-" : s.pose_channel.c_str(), inputsName(s.inputs), clocksName(s.clocks),
                static_cast<long long>(s.scans_in), static_cast<long long>(s.scans_mapped),
                static_cast<long long>(scansDropped(s)), static_cast<long long>(s.scans_rejected),
                static_cast<long long>(s.poses_in), last, s.trail.size());
  }
}

// The same as one JSON object: {"utime":..., "sources":[{...,"trail":[[x,y,z],...]}]}.
void printSourcesJson(const ogf::mapper_status_t& m) {
  std::string out = "{\"utime\":" + std::to_string(m.utime) + ",\"sources\":[";
  for (std::size_t i = 0; i < m.sources.size(); ++i) {
    const auto& s = m.sources[i];
    if (i > 0) out += ',';
    out += "{\"robot\":" + ogf::jsonString(s.robot) + ",\"sensor\":" + ogf::jsonString(s.name) +
           ",\"channel\":" + ogf::jsonString(s.scan_channel) + ",\"packets\":" + (s.packets ? "true" : "false") +
           ",\"pose_channel\":" + ogf::jsonString(s.pose_channel) + ",\"inputs\":\"" + inputsName(s.inputs) +
           "\",\"clocks\":\"" + clocksName(s.clocks) + "\",\"clock_offset_us\":" +
           std::to_string(s.clock_offset_us);
    for (const auto& [key, value] : {std::pair<const char*, std::int64_t>{"scans_in", s.scans_in},
                                     {"scans_mapped", s.scans_mapped},
                                     {"scans_dropped", scansDropped(s)},
                                     {"scans_rejected", s.scans_rejected},
                                     {"scans_throttled", s.scans_throttled},
                                     {"packets_in", s.packets_in},
                                     {"packets_rejected", s.packets_rejected},
                                     {"poses_in", s.poses_in},
                                     {"poses_rejected", s.poses_rejected}})
      out += std::string(",\"") + key + "\":" + std::to_string(value);
    out += ",\"trail\":[";
    for (std::size_t k = 0; k < s.trail.size(); ++k) {
      char p[96];
      std::snprintf(p, sizeof p, "%s[%.3f,%.3f,%.3f]", k > 0 ? "," : "", static_cast<double>(s.trail[k][0]),
                    static_cast<double>(s.trail[k][1]), static_cast<double>(s.trail[k][2]));
      out += p;
    }
    out += "]}";
  }
  std::printf("%s]}\n", out.c_str());
}

// Handles the bus until `done` says so or `timeout_s` passes.
void handleUntil(lcm::LCM& lcm, double timeout_s, const std::function<bool()>& done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!done() && std::chrono::steady_clock::now() < deadline) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    lcm.handleTimeout(static_cast<int>(std::max<std::int64_t>(1, left.count())));
  }
}

// Waits up to `timeout_s` for the reply with `id` on `channel`.
template <class Reply>
std::optional<Reply> awaitReply(lcm::LCM& lcm, const std::string& channel, std::int64_t id, double timeout_s,
                                const std::function<void()>& send) {
  std::optional<Reply> reply;
  ogf::transport::Subscriber<Reply> sub(
      lcm, channel,
      [&](const Reply& r, const lcm::ReceiveBuffer&, const std::string&) {
        if (r.request_id == id) reply = r;
      },
      [](const std::string& ch, std::size_t size, const std::string& why) {
        spdlog::warn("reply on {} ({} bytes) {}", ch, size, why);
      });
  send();
  handleUntil(lcm, timeout_s, [&] { return reply.has_value(); });
  return reply;
}

int noReply(const std::string& channel, double timeout_s, const std::string& url) {
  std::fprintf(stderr, "no reply on %s_REPLY within %.1f s: is ogf-mapper running on %s?\n", channel.c_str(), timeout_s,
               url.c_str());
  return kExitFailed;
}

// The command line: the bus options and one subcommand.
struct Options {
  std::string url, query_channel = "OGF_MAP_QUERY", command_channel = "OGF_MAP_COMMAND", log_level = "warn";
  std::string status_channel = "OGF_MAPPER_STATUS";
  bool json = false;
  double timeout_s = 5.0;
  std::vector<double> cell_xyz, box;
  std::string key_file, keygen_file;
  std::string format, path;
  CLI::App* cell = nullptr;
  CLI::App* box_command = nullptr;
  CLI::App* keygen = nullptr;
  CLI::App* sources = nullptr;
};

void addOptions(CLI::App& app, Options& o) {
  app.require_subcommand(1);
  app.add_option("--lcm-url", o.url, "LCM URL (default: $LCM_DEFAULT_URL, else LCM's default)");
  app.add_option("--query-channel", o.query_channel, "Query channel")->capture_default_str();
  app.add_option("--command-channel", o.command_channel, "Command channel")->capture_default_str();
  app.add_option("--timeout", o.timeout_s, "Seconds to wait for the reply")->capture_default_str()->check(ogf::cli::positive());
  app.add_option("--log-level", o.log_level, "trace, debug, info, warn, error")->capture_default_str();
  o.cell = app.add_subcommand("cell", "Probability, class, mean, variance and entropy of the cells holding points");
  o.cell->add_option("xyz", o.cell_xyz, "X Y Z [X Y Z ...], metres")->required()->expected(3, 3 * 10'000);
  o.box_command = app.add_subcommand("box", "Known and unknown volume and mean entropy of a box");
  o.box_command->add_option("corners", o.box, "XMIN YMIN ZMIN XMAX YMAX ZMAX, metres")->required()->expected(6);
  app.add_option("--key", o.key_file,
                 "Key file to sign commands with (the mapper's services.key_file; 64 hex digits, mode 0600)");
  o.keygen = app.add_subcommand("keygen", "Create a new key file (mode 0600) for services.key_file; nothing is sent");
  o.keygen->add_option("file", o.keygen_file, "Where to create it (never replaced)")->required();
  o.sources = app.add_subcommand(
      "sources", "Each source of scans the mapper maps (from its status): robot, sensor, channels, state, counts, "
                 "last position and trail length");
  o.sources->fallthrough();  // its options are the program's, so they may follow it: sources --json
  app.add_flag("--json", o.json, "sources: one JSON object, with each source's whole trail");
  app.add_option("--status-channel", o.status_channel, "sources: the mapper's status channel")->capture_default_str();
  app.add_subcommand("save", "Write a snapshot to the mapper's state directory now");
  app.add_subcommand("reset", "Start an empty map with a new map id (the old one is kept on disk)");
  auto* exp = app.add_subcommand("export", "Write the map into the mapper's export directory (services.export_dir)");
  exp->add_option("format", o.format, "ogfm, ply, pcd, csv or bt")->required();
  exp->add_option("name", o.path, "Plain file name ending in .FORMAT (no directory); an existing file is kept")->required();
}

int keygen(const Options& o) {
  if (auto st = ogf::mapper_daemon::createCommandKey(o.keygen_file); !st) {
    std::fprintf(stderr, "keygen: %s\n", st.error().message.c_str());
    return kExitFailed;
  }
  std::printf("wrote a new key to %s (mode 0600)\n", o.keygen_file.c_str());
  return kExitOk;
}

// --key's key, and the cell subcommand's points checked, before anything is sent.
std::optional<int> checkUsage(const Options& o, std::optional<ogf::mapper_daemon::CommandKey>& key) {
  if (!o.key_file.empty()) {
    auto k = ogf::mapper_daemon::loadCommandKey(o.key_file);
    if (!k) {
      std::fprintf(stderr, "--key: %s\n", k.error().message.c_str());
      return kExitUsage;
    }
    key = *k;
  }
  if (o.cell->parsed() && o.cell_xyz.size() % 3 != 0) {
    std::fprintf(stderr, "cell: give X Y Z triples (%zu numbers given)\n", o.cell_xyz.size());
    return kExitUsage;
  }
  return std::nullopt;
}

// Who asks, under which request id: one per run.
struct Request {
  std::mt19937_64 rng{std::random_device{}()};  // first: the id is its first draw, a command's nonce the next
  std::int64_t id = static_cast<std::int64_t>(rng() >> 1);
  std::string requester = "ogf-map-query:" + std::to_string(::getpid());
};

ogf::map_query_t makeQuery(const Options& o, const Request& request) {
  ogf::map_query_t q{};
  q.utime = nowUtime();
  q.request_id = request.id;
  q.requester = request.requester;
  if (o.cell->parsed()) {
    q.kind = ogf::map_query_t::KIND_CELLS;
    for (std::size_t i = 0; i + 2 < o.cell_xyz.size(); i += 3) {
      q.points.push_back({static_cast<float>(o.cell_xyz[i]), static_cast<float>(o.cell_xyz[i + 1]),
                          static_cast<float>(o.cell_xyz[i + 2])});
    }
    q.num_points = static_cast<std::int32_t>(q.points.size());
  } else {
    q.kind = ogf::map_query_t::KIND_BOX;
    for (int a = 0; a < 3; ++a) {
      q.box_min[a] = static_cast<float>(o.box[static_cast<std::size_t>(a)]);
      q.box_max[a] = static_cast<float>(o.box[static_cast<std::size_t>(a) + 3]);
    }
  }
  return q;
}

void printQueryReply(const ogf::map_query_t& q, const ogf::map_query_reply_t& r) {
  std::printf("map_id %lld seq %lld resolution %.3f\n", static_cast<long long>(r.map_id),
              static_cast<long long>(r.seq), static_cast<double>(r.resolution));
  if (q.kind == ogf::map_query_t::KIND_CELLS) {
    std::printf("%10s %10s %10s %11s %6s %10s %10s %8s\n", "x", "y", "z", "probability", "class", "mean", "variance",
                "entropy");
    for (std::size_t i = 0; i < static_cast<std::size_t>(r.num_cells); ++i) {
      const char* cls = r.cell_class[i] > 0 ? "occ" : r.cell_class[i] < 0 ? "free" : "unk";
      std::printf("%10.3f %10.3f %10.3f %11.4f %6s %10.4f %10.4f %8.4f\n", static_cast<double>(q.points[i][0]),
                  static_cast<double>(q.points[i][1]), static_cast<double>(q.points[i][2]),
                  static_cast<double>(r.probability[i]), cls, static_cast<double>(r.mean[i]),
                  static_cast<double>(r.variance[i]), static_cast<double>(r.entropy[i]));
    }
  } else {
    std::printf("cells %lld occupied %lld free %lld unknown %lld\n", static_cast<long long>(r.box_cells),
                static_cast<long long>(r.box_occupied), static_cast<long long>(r.box_free),
                static_cast<long long>(r.box_unknown));
    std::printf("known_volume_m3 %.3f unknown_volume_m3 %.3f mean_entropy_bits %.4f mean_variance %.4f\n",
                r.known_volume_m3, r.unknown_volume_m3, r.mean_entropy_bits, r.mean_variance);
  }
}

int query(const Options& o, lcm::LCM& lcm, const std::string& url, const Request& request) {
  const ogf::map_query_t q = makeQuery(o, request);
  const auto r = awaitReply<ogf::map_query_reply_t>(lcm, o.query_channel + "_REPLY", request.id, o.timeout_s,
                                                    [&] { lcm.publish(o.query_channel, &q); });
  if (!r) return noReply(o.query_channel, o.timeout_s, url);
  if (r->status != ogf::map_query_reply_t::STATUS_OK) {
    std::fprintf(stderr, "refused: %s\n", r->message.c_str());
    return kExitFailed;
  }
  printQueryReply(q, *r);
  return kExitOk;
}

// The next mapper status on the bus, printed as a table or JSON.
int sources(const Options& o, lcm::LCM& lcm, const std::string& url) {
  std::optional<ogf::mapper_status_t> status;
  ogf::transport::Subscriber<ogf::mapper_status_t> sub(
      lcm, o.status_channel,
      [&](const ogf::mapper_status_t& m, const lcm::ReceiveBuffer&, const std::string&) { status = m; },
      [](const std::string& ch, std::size_t size, const std::string& why) {
        spdlog::warn("message on {} ({} bytes) {}", ch, size, why);
      });
  handleUntil(lcm, o.timeout_s, [&] { return status.has_value(); });
  if (!status) {
    std::fprintf(stderr, "no status on %s within %.1f s: is ogf-mapper running on %s?\n", o.status_channel.c_str(),
                 o.timeout_s, url.c_str());
    return kExitFailed;
  }
  if (o.json) {
    printSourcesJson(*status);
  } else {
    printSources(*status);
  }
  return kExitOk;
}

int command(const CLI::App& app, const Options& o, lcm::LCM& lcm, const std::string& url, Request& request,
            const std::optional<ogf::mapper_daemon::CommandKey>& key) {
  ogf::map_command_t c{};
  c.utime = nowUtime();
  c.request_id = request.id;
  c.requester = request.requester;
  for (const char* name : {"save", "reset", "export"}) {
    if (app.got_subcommand(name)) c.command = name;
  }
  c.format = o.format;
  c.path = o.path;
  c.nonce = static_cast<std::int64_t>(request.rng());
  // Unsigned without --key: the mapper refuses it, and says why.
  if (key) ogf::mapper_daemon::signCommand(c, *key);
  const auto r = awaitReply<ogf::map_command_reply_t>(lcm, o.command_channel + "_REPLY", request.id, o.timeout_s,
                                                      [&] { lcm.publish(o.command_channel, &c); });
  if (!r) return noReply(o.command_channel, o.timeout_s, url);
  std::printf("%s: %s (map_id %lld seq %lld)\n", r->status == ogf::map_command_reply_t::STATUS_OK ? "done" : "not done",
              r->message.c_str(), static_cast<long long>(r->map_id), static_cast<long long>(r->seq));
  if (r->status == ogf::map_command_reply_t::STATUS_REFUSED && !key)
    std::fprintf(stderr, "commands are signed with --key FILE (the mapper's services.key_file)\n");
  return r->status == ogf::map_command_reply_t::STATUS_OK ? kExitOk : kExitFailed;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Ask the running ogf-mapper about its map, or order it, over LCM (OGF_MAP_QUERY / OGF_MAP_COMMAND; the\n"
      "replies come on <channel>_REPLY), or list its sources from its status (OGF_MAPPER_STATUS). Coordinates\n"
      "are metres in the map frame.\n"
      "Exit 0 when answered or done, 1 when refused, failed or unanswered within --timeout, 2 on bad usage."};
  Options o;
  addOptions(app, o);
  OGF_PARSE_COMMAND_LINE(app, argc, argv);
  if (o.keygen->parsed()) return keygen(o);
  std::optional<ogf::mapper_daemon::CommandKey> key;
  if (auto stop = checkUsage(o, key)) return *stop;
  if (!ogf::transport::setupLoggingAt("ogf-map-query", "--log-level", o.log_level)) return kExitUsage;
  const std::string resolved = ogf::transport::withReceiveBuffer(ogf::transport::resolveLcmUrl(o.url));
  lcm::LCM lcm(resolved);
  if (!lcm.good()) {
    spdlog::error("cannot join the LCM bus {}", resolved);
    return kExitFailed;
  }
  if (const auto why = ogf::transport::receiveProblem(lcm, resolved)) {
    spdlog::error("{}", *why);
    return kExitFailed;
  }
  if (o.sources->parsed()) return sources(o, lcm, resolved);
  Request request;
  if (o.cell->parsed() || o.box_command->parsed()) return query(o, lcm, resolved, request);
  return command(app, o, lcm, resolved, request, key);
}
