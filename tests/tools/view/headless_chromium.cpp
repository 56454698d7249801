#include "headless_chromium.hpp"

#include <unistd.h>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = boost::asio::ip::tcp;

namespace ogf::testing {
namespace {

std::string chromiumPath() {
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (::access(p, X_OK) == 0) return p;
  return "";
}

std::optional<std::vector<std::uint8_t>> base64Decode(const std::string& in) {
  std::vector<std::uint8_t> out;
  out.reserve(in.size() * 3 / 4);
  std::uint32_t acc = 0;
  int bits = 0;
  for (const char c : in) {
    int v = -1;
    if (c >= 'A' && c <= 'Z') v = c - 'A';
    else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
    else if (c >= '0' && c <= '9') v = c - '0' + 52;
    else if (c == '+') v = 62;
    else if (c == '/') v = 63;
    else if (c == '=') break;
    else return std::nullopt;
    acc = (acc << 6) | static_cast<std::uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<std::uint8_t>((acc >> bits) & 0xFF));
    }
  }
  return out;
}

}  // namespace

std::optional<std::string> jsonString(const std::string& json, const std::string& key) {
  const std::string needle = "\"" + key + "\"";
  auto at = json.find(needle);
  if (at == std::string::npos) return std::nullopt;
  at = json.find('"', json.find(':', at + needle.size()));
  if (at == std::string::npos) return std::nullopt;
  std::string out;
  for (std::size_t i = at + 1; i < json.size(); ++i) {
    if (json[i] == '\\' && i + 1 < json.size()) {
      out += json[++i];
    } else if (json[i] == '"') {
      return out;
    } else {
      out += json[i];
    }
  }
  return std::nullopt;
}

struct HeadlessChromium::Connection {
  boost::asio::io_context io;
  websocket::stream<beast::tcp_stream> ws{io};
};

HeadlessChromium::HeadlessChromium() {
  const auto base = std::filesystem::temp_directory_path() / ("ogf-chromium-" + std::to_string(::getpid()));
  profile_dir_ = (base / "profile").string();
  log_path_ = (base / "chromium.log").string();
  std::filesystem::create_directories(profile_dir_);
}

HeadlessChromium::~HeadlessChromium() {
  connection_.reset();
  if (process_ && process_->started()) {
    process_->signal(SIGTERM);
    if (!process_->wait(std::chrono::seconds(10))) {
      process_->signal(SIGKILL);
      process_->wait(std::chrono::seconds(5));
    }
  }
  std::error_code ec;
  std::filesystem::remove_all(std::filesystem::path(profile_dir_).parent_path(), ec);
}

std::string HeadlessChromium::log() const {
  std::ifstream in(log_path_);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::optional<std::string> HeadlessChromium::start(int width, int height) {
  const std::string exe = chromiumPath();
  if (exe.empty()) return "chromium is not installed (apt-get install chromium)";
  process_ = std::make_unique<ChildProcess>(
      std::vector<std::string>{exe, "--headless", "--no-sandbox", "--use-gl=angle", "--use-angle=swiftshader",
                               "--enable-unsafe-swiftshader", "--remote-debugging-port=0",
                               "--remote-debugging-address=127.0.0.1", "--user-data-dir=" + profile_dir_,
                               "--window-size=" + std::to_string(width) + "," + std::to_string(height),
                               "--hide-scrollbars", "--no-first-run", "--no-default-browser-check", "--mute-audio",
                               "about:blank"},
      log_path_);
  if (!process_->started()) return "chromium did not start";
  // "DevTools listening on ws://127.0.0.1:PORT/devtools/browser/ID" once it is up.
  const std::regex listening(R"(DevTools listening on ws://([0-9.]+):([0-9]+)/)");
  std::smatch m;
  std::string host, port;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < deadline) {
    const std::string text = log();
    if (std::regex_search(text, m, listening)) {
      host = m[1];
      port = m[2];
      break;
    }
    if (process_->wait(std::chrono::milliseconds(100))) return "chromium exited at start: " + text.substr(0, 2000);
  }
  if (port.empty()) return "chromium did not open its DevTools port within 30 s";

  // The page target's WebSocket from /json/list.
  std::string page_path;
  for (int attempt = 0; attempt < 50 && page_path.empty(); ++attempt) {
    try {
      boost::asio::io_context io;
      beast::tcp_stream stream(io);
      stream.connect(tcp::endpoint(boost::asio::ip::make_address(host), static_cast<unsigned short>(std::stoi(port))));
      http::request<http::empty_body> req(http::verb::get, "/json/list", 11);
      req.set(http::field::host, host + ":" + port);
      http::write(stream, req);
      beast::flat_buffer buffer;
      http::response<http::string_body> res;
      http::read(stream, buffer, res);
      const std::regex page_ws(R"re("type":\s*"page"[^}]*?"webSocketDebuggerUrl":\s*"ws://[^/]+(/devtools/page/[^"]+)")re");
      const std::string body = res.body();
      if (std::regex_search(body, m, page_ws)) page_path = m[1];
    } catch (const std::exception&) {
    }
    if (page_path.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  if (page_path.empty()) return "chromium lists no page target";
  try {
    connection_ = std::make_unique<Connection>();
    beast::get_lowest_layer(connection_->ws)
        .connect(tcp::endpoint(boost::asio::ip::make_address(host), static_cast<unsigned short>(std::stoi(port))));
    connection_->ws.handshake(host + ":" + port, page_path);
    connection_->ws.read_message_max(std::size_t{256} << 20);
  } catch (const std::exception& e) {
    return std::string("cannot reach chromium's DevTools: ") + e.what();
  }
  if (!call("Page.enable", "{}")) return "chromium does not answer DevTools commands";
  return std::nullopt;
}

std::optional<std::string> HeadlessChromium::call(const std::string& method, const std::string& params_json) {
  if (!connection_) return std::nullopt;
  const int id = next_id_++;
  const std::string msg = "{\"id\":" + std::to_string(id) + ",\"method\":\"" + method + "\",\"params\":" + params_json + "}";
  auto& ws = connection_->ws;
  try {
    ws.text(true);
    ws.write(boost::asio::buffer(msg));
  } catch (const std::exception&) {
    return std::nullopt;
  }
  const std::string id_field = "\"id\":" + std::to_string(id) + ",";
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (std::chrono::steady_clock::now() < deadline) {
    beast::flat_buffer buffer;
    bool done = false;
    beast::error_code ec;
    ws.async_read(buffer, [&](beast::error_code e, std::size_t) {
      ec = e;
      done = true;
    });
    connection_->io.restart();
    connection_->io.run_for(deadline - std::chrono::steady_clock::now());
    if (!done) {
      beast::get_lowest_layer(ws).cancel();
      connection_->io.restart();
      connection_->io.run();
      return std::nullopt;
    }
    if (ec) return std::nullopt;
    std::string text = beast::buffers_to_string(buffer.data());
    if (text.rfind("{" + id_field, 0) == 0 || text.find(id_field) != std::string::npos) {
      if (text.find("\"error\":") != std::string::npos && text.find("\"result\":") == std::string::npos) return std::nullopt;
      return text;
    }
  }
  return std::nullopt;
}

bool HeadlessChromium::open(const std::string& url) {
  return call("Page.navigate", "{\"url\":\"" + url + "\"}").has_value();
}

std::string HeadlessChromium::evaluate(const std::string& expression) {
  std::string quoted;
  for (const char c : expression) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  const auto r = call("Runtime.evaluate", "{\"expression\":\"String(" + quoted + ")\",\"returnByValue\":true}");
  if (!r) return "";
  return jsonString(*r, "value").value_or("");
}

std::string HeadlessChromium::title() { return evaluate("document.title"); }

std::string HeadlessChromium::waitForTitle(const std::string& text, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  std::string t;
  while (true) {
    t = title();
    if (t.find(text) != std::string::npos || std::chrono::steady_clock::now() >= deadline) return t;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

std::vector<std::uint8_t> HeadlessChromium::screenshotPng() {
  const auto r = call("Page.captureScreenshot", R"({"format":"png"})");
  if (!r) return {};
  const auto data = jsonString(*r, "data");
  if (!data) return {};
  return base64Decode(*data).value_or(std::vector<std::uint8_t>{});
}

}  // namespace ogf::testing
