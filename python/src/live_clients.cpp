// ogf.MapClient and ogf.NavClient (live_clients.hpp).
#include "live_clients.hpp"

#include <pybind11/stl.h>

#include <ogf/map_delta_t.hpp>
#include <ogf/nav_grid_t.hpp>

#include <ogf/delta/map_receiver.hpp>
#include <ogf/navigation/nav_receiver.hpp>

#include <optional>
#include <string>
#include <vector>

#include "cell_arrays.hpp"
#include "nav_grid_view.hpp"
#include "stream_follower.hpp"

namespace py = pybind11;

namespace ogf::python {
namespace {

using MapFollower = StreamFollower<ogf::map_delta_t, delta::MapReceiver>;
using NavFollower = StreamFollower<ogf::nav_grid_t, navigation::NavReceiver>;

// The dense grid NavClient.grid() builds at most unless asked for more.
constexpr std::int64_t kDefaultGridColumns = std::int64_t{1} << 24;

// The map client: the follower and the arrays of the map it rebuilt, made again when messages arrived since.
struct MapClient {
  MapClient(const std::optional<std::string>& url, const std::string& channel, const std::string& request_channel)
      : follower(url, channel, request_channel) {}

  const CellArrays& arrays() {
    const std::uint64_t messages = follower.messages();
    if (!cached || cached_at != messages) {
      std::vector<delta::PublishedCell> cells;
      double resolution = 0.0;
      {
        py::gil_scoped_release unlocked;
        follower.withReceiver([&](const delta::MapReceiver& r) {
          cells = r.map().sortedCells();
          resolution = r.resolution();
          return 0;
        });
      }
      cached = CellArrays::build(cells.size(), resolution, [&](std::size_t i) {
        const auto& c = cells[i];
        return CellRow{c.key, static_cast<double>(c.probability) / delta::kProbabilityScale, c.variance, c.cell_class};
      });
      cached_at = messages;
    }
    return *cached;
  }

  MapFollower follower;
  std::optional<CellArrays> cached;
  std::uint64_t cached_at = 0;
};

// Properties both clients have, from their receivers.
template <class Class, class Follow>
void defineStreamProperties(Class& cls, Follow follower, const char* what) {
  using Self = typename Class::type;
  cls.def("poll", [follower](Self& self, double timeout_s) { return follower(self).poll(timeout_s); },
          py::arg("timeout_s"),
          (std::string("Handles the bus for timeout_s seconds (without the GIL), applying every ") + what +
           " message and asking for a keyframe when needed; returns the number of messages received.")
              .c_str())
      .def("wait_consistent",
           [follower](Self& self, double timeout_s) { return follower(self).waitConsistent(timeout_s); },
           py::arg("timeout_s"),
           "Handles the bus until what this client rebuilt equals the mapper's (its checksum equals the one the "
           "mapper stamped on the last message applied) or timeout_s passes; True when consistent.")
      .def_property_readonly(
          "seq", [follower](Self& self) { return follower(self).withReceiver([](const auto& r) { return r.appliedSeq(); }); },
          "The mapper's update sequence number of the last update applied; -1 before the first keyframe.")
      .def_property_readonly(
          "map_id",
          [follower](Self& self) { return follower(self).withReceiver([](const auto& r) { return r.mapId(); }); },
          "The id of the map the mapper publishes (it changes when the mapper starts a new map); None before the "
          "first message.")
      .def_property_readonly(
          "server_checksum",
          [follower](Self& self) { return follower(self).withReceiver([](const auto& r) { return r.serverChecksum(); }); },
          "The checksum the mapper stamped on the last message applied; None before the first.")
      .def_property_readonly(
          "consistent",
          [follower](Self& self) {
            return follower(self).withReceiver([](const auto& r) { return !r.needsKeyframe() && r.consistent(); });
          },
          "True when this client's checksum equals the mapper's: nothing was missed.")
      .def_property_readonly(
          "needs_keyframe",
          [follower](Self& self) { return follower(self).withReceiver([](const auto& r) { return r.needsKeyframe(); }); },
          "True while the client waits for a keyframe (at start, after a gap): it asks for one every second.")
      .def_property_readonly(
          "dropped",
          [follower](Self& self) { return follower(self).withReceiver([](const auto& r) { return r.dropped(); }); },
          "Updates and keyframes dropped because the parts waiting to complete held more than their bound (64 MiB "
          "for the map, 16 MiB for the grid, besides what is applied): anyone on the bus can send parts that never "
          "complete.")
      .def_property_readonly(
          "gaps", [follower](Self& self) { return follower(self).withReceiver([](const auto& r) { return r.gaps(); }); },
          "Updates lost on the bus so far (each answered with a keyframe request).")
      .def_property_readonly(
          "keyframes",
          [follower](Self& self) { return follower(self).withReceiver([](const auto& r) { return r.keyframesApplied(); }); },
          "Keyframes applied so far.")
      .def_property_readonly("malformed", [follower](Self& self) { return follower(self).malformed(); },
                             "Messages ignored because they did not decode or did not agree with themselves.")
      .def_property_readonly("messages", [follower](Self& self) { return follower(self).messages(); },
                             "Messages received so far.")
      .def_property_readonly("lcm_url", [follower](Self& self) { return follower(self).url(); },
                             "The LCM URL the client joined.")
      .def_property_readonly("channel", [follower](Self& self) { return follower(self).channel(); },
                             "The channel the client follows.");
}

}  // namespace

void defineLiveClients(py::module_& m) {
  py::class_<MapClient> map_client(
      m, "MapClient",
      "Follows the mapper's 3-D map live: rebuilds it from the delta stream (OGF_MAP_DELTA), asking for a keyframe "
      "on OGF_MAP_REQUEST at start and after a gap, as ogf-map-client does. lcm_url None means $LCM_DEFAULT_URL, "
      "else LCM's default. The map is the same arrays as ogf.Map's, in cell-key order (x, then y, then z), with "
      "the probability quantised as the deltas carry it. ValueError when the URL cannot be joined or received on.");
  map_client.def(py::init<const std::optional<std::string>&, const std::string&, const std::string&>(),
                 py::arg("lcm_url") = py::none(), py::arg("channel") = "OGF_MAP_DELTA",
                 py::arg("request_channel") = "OGF_MAP_REQUEST",
                 "Joins the bus and subscribes to `channel`; nothing is received until poll() or wait_consistent().");
  defineStreamProperties(map_client, [](MapClient& c) -> MapFollower& { return c.follower; }, "OGF_MAP_DELTA");
  defineCellArrayProperties(map_client, [](MapClient& c) -> const CellArrays& { return c.arrays(); });
  map_client
      .def_property_readonly(
          "checksum",
          [](MapClient& c) { return c.follower.withReceiver([](const delta::MapReceiver& r) { return r.map().checksum(); }); },
          "The checksum of the map this client rebuilt (ogf-map-client's published_checksum).")
      .def_property_readonly(
          "resolution",
          [](MapClient& c) { return c.follower.withReceiver([](const delta::MapReceiver& r) { return r.resolution(); }); },
          "Cell size, metres (0 before the first keyframe).")
      .def("__len__",
           [](MapClient& c) { return c.follower.withReceiver([](const delta::MapReceiver& r) { return r.map().size(); }); },
           "The number of cells of the rebuilt map.");

  py::class_<NavFollower> nav_client(
      m, "NavClient",
      "Follows the mapper's 2-D navigation grid live: rebuilds it from OGF_NAV_GRID (changed tiles between full "
      "keyframes), asking for a keyframe on OGF_NAV_REQUEST at start and after a gap. lcm_url None means "
      "$LCM_DEFAULT_URL, else LCM's default. ValueError when the URL cannot be joined or received on.");
  nav_client.def(py::init<const std::optional<std::string>&, const std::string&, const std::string&>(),
                 py::arg("lcm_url") = py::none(), py::arg("channel") = "OGF_NAV_GRID",
                 py::arg("request_channel") = "OGF_NAV_REQUEST",
                 "Joins the bus and subscribes to `channel`; nothing is received until poll() or wait_consistent().");
  defineStreamProperties(nav_client, [](NavFollower& f) -> NavFollower& { return f; }, "OGF_NAV_GRID");
  nav_client
      .def(
          "grid",
          [](NavFollower& f, std::int64_t max_columns) {
            if (max_columns < 1 || max_columns > navigation::kMaxDenseColumns)
              raiseValueError("max_columns must be from 1 to 2^28");
            std::optional<Result<navigation::NavGrid>> grid;
            {
              py::gil_scoped_release unlocked;
              grid = f.withReceiver([&](const navigation::NavReceiver& r) { return r.grid(max_columns); });
            }
            if (!*grid) raiseValueError((*grid).error().message);
            return NavGridView::of(std::move(**grid));
          },
          py::arg("max_columns") = kDefaultGridColumns,
          "The grid rebuilt so far, as an ogf.NavGrid (empty, width 0, before the first keyframe). ValueError "
          "naming the limit when its known columns span more than max_columns (default 2^24, a square of 410 m "
          "at 0.1 m, 32 MB; at most 2^28): columns far apart, as a forged message can name, would otherwise "
          "make a rectangle of gigabytes.")
      .def_property_readonly(
          "checksum",
          [](NavFollower& f) { return f.withReceiver([](const navigation::NavReceiver& r) { return r.checksum(); }); },
          "The checksum of the grid this client rebuilt.")
      .def_property_readonly(
          "known_columns",
          [](NavFollower& f) { return f.withReceiver([](const navigation::NavReceiver& r) { return r.knownColumns(); }); },
          "How many columns of the rebuilt grid are free or occupied.");
}

}  // namespace ogf::python
