// Test helper: Debian's Chromium, headless, driven over the DevTools protocol (a WebSocket, spoken here
// with Boost.Beast): open a page, read its title, take a screenshot. WebGL runs on SwiftShader, so no GPU
// is needed. start() says why when Chromium cannot run here, so a test can skip with that reason.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "png_image.hpp"
#include "support/child_process.hpp"

namespace ogf::testing {

class HeadlessChromium {
 public:
  HeadlessChromium();
  ~HeadlessChromium();
  HeadlessChromium(const HeadlessChromium&) = delete;
  HeadlessChromium& operator=(const HeadlessChromium&) = delete;

  // Starts the browser with a window of width × height; nullopt when ready, else why it cannot run.
  std::optional<std::string> start(int width, int height);
  // Loads `url` in the page; false when the browser does not answer.
  bool open(const std::string& url);
  // The value of a JavaScript expression in the page, as a string ("" when the browser does not answer).
  std::string evaluate(const std::string& expression);
  // The page's title ("" when the browser does not answer).
  std::string title();
  // Polls the title until it contains `text` or `timeout` passes; the last title seen.
  std::string waitForTitle(const std::string& text, std::chrono::milliseconds timeout);
  // The viewport as PNG bytes (empty on failure).
  std::vector<std::uint8_t> screenshotPng();

  std::string log() const;

 private:
  struct Connection;
  // Sends a DevTools command and returns its result message (nullopt on timeout or error).
  std::optional<std::string> call(const std::string& method, const std::string& params_json);

  std::string profile_dir_;
  std::string log_path_;
  std::unique_ptr<ChildProcess> process_;
  std::unique_ptr<Connection> connection_;
  int next_id_ = 1;
};

// The first JSON string value of `key` in `json` (escapes \" and \\ undone), or nullopt.
std::optional<std::string> jsonString(const std::string& json, const std::string& key);

}  // namespace ogf::testing
