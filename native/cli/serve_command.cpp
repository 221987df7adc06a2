// `bakegi serve folder`: the web page's server (issue 16, §4 of the grid's paper), on the
// loopback interface only. cpp-httplib (Debian's libcpp-httplib-dev) does the HTTP; this file
// maps the stream's packets (web_stream.h) and the folder's files onto URLs:
//   GET /stream/manifest.json?vectors=V&vertices=N&encoding=quantized|factored
//   GET /stream/packet/K?vectors=V&vertices=N&encoding=...      (binary)
//   GET /anything-else                                          the folder's files
// Streams are made once per (V, N, encoding) and kept.
#if BAKEGI_HAS_HTTPLIB
#include <httplib.h>
#endif

#include <csignal>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <tuple>

#include "arguments.h"
#include "commands.h"
#include "exit_codes.h"
#include "file_error.h"
#include "usage_error.h"
#include "web_stream.h"

namespace bakegi::cli {

#if BAKEGI_HAS_HTTPLIB

namespace {

httplib::Server* running_server = nullptr;

void stop_on_signal(int) {
  if (running_server) running_server->stop();
}

class StreamCache {
 public:
  StreamCache(std::filesystem::path folder, StreamSettings defaults)
      : folder_(std::move(folder)), defaults_(defaults) {}

  // The stream a request's query asks for; throws FileError / UsageError.
  const SceneStream& stream_for(const httplib::Request& request) {
    StreamSettings settings = defaults_;
    if (request.has_param("vectors")) {
      settings.vectors_per_request =
          uint32_t(parse_int(request.get_param_value("vectors"), "vectors", 1, 1 << 24));
    }
    if (request.has_param("vertices")) {
      settings.vertices_per_packet =
          uint32_t(parse_int(request.get_param_value("vertices"), "vertices", 1, 1 << 26));
    }
    if (request.has_param("encoding")) {
      const std::string encoding = request.get_param_value("encoding");
      if (encoding != "quantized" && encoding != "factored") {
        throw UsageError("encoding must be quantized or factored");
      }
      settings.quantized = encoding == "quantized";
    }
    const auto key = std::make_tuple(settings.vectors_per_request, settings.vertices_per_packet,
                                     settings.quantized);
    std::lock_guard<std::mutex> lock(mutex_);
    auto found = streams_.find(key);
    if (found == streams_.end()) {
      found = streams_.emplace(key, std::make_unique<SceneStream>(folder_, settings)).first;
    }
    return *found->second;
  }

 private:
  std::filesystem::path folder_;
  StreamSettings defaults_;
  std::mutex mutex_;
  std::map<std::tuple<uint32_t, uint32_t, bool>, std::unique_ptr<SceneStream>> streams_;
};

// Runs `body`; a bad request or folder becomes a 4xx/5xx answer with the message as text.
template <typename Body>
void answer(httplib::Response& response, Body&& body) {
  try {
    body();
  } catch (const UsageError& error) {
    response.status = 400;
    response.set_content(error.what(), "text/plain");
  } catch (const std::exception& error) {
    response.status = 500;
    response.set_content(error.what(), "text/plain");
  }
}

}  // namespace

int run_serve_command(const std::vector<std::string>& words) {
  const Arguments args(words, {{"port"}, {"vectors"}, {"vertices"}, {"float", false}});
  if (args.positional().size() != 1) throw UsageError("serve expects one scene folder");
  const std::filesystem::path folder = args.positional()[0];
  StreamSettings defaults;
  defaults.vectors_per_request = uint32_t(args.int_value("vectors", 512, 1, 1 << 24));
  defaults.vertices_per_packet = uint32_t(args.int_value("vertices", 4096, 1, 1 << 26));
  defaults.quantized = !args.has("float");
  const int64_t port = args.int_value("port", 8080, 0, 65535);

  StreamCache cache(folder, defaults);
  cache.stream_for(httplib::Request());  // a folder that cannot stream fails here, at start

  httplib::Server server;
  // Packets go out as soon as written: with Nagle's algorithm each request waited for the
  // client's delayed acknowledgement (30 ms a packet, measured).
  server.set_tcp_nodelay(true);
  server.Get(
      "/stream/manifest.json", [&](const httplib::Request& request, httplib::Response& response) {
        answer(response, [&] {
          response.set_content(cache.stream_for(request).manifest_json(), "application/json");
        });
      });
  server.Get(R"(/stream/packet/(\d+))",
             [&](const httplib::Request& request, httplib::Response& response) {
               answer(response, [&] {
                 const SceneStream& stream = cache.stream_for(request);
                 const int64_t index = parse_int(request.matches[1], "packet", 0, 1 << 30);
                 if (size_t(index) >= stream.packet_count()) {
                   response.status = 404;
                   response.set_content("no packet " + std::to_string(index), "text/plain");
                   return;
                 }
                 const std::vector<uint8_t>& bytes = stream.packet(size_t(index));
                 response.set_content(reinterpret_cast<const char*>(bytes.data()), bytes.size(),
                                      "application/octet-stream");
               });
             });
  server.set_file_extension_and_mimetype_mapping("gltf", "model/gltf+json");
  // A JavaScript type that Debian's cpp-httplib does not compress: it would brotli the
  // page's 0.8 MB script at its slowest setting on every request (2 s before the page
  // starts, measured in Chromium).
  server.set_file_extension_and_mimetype_mapping("js", "application/x-javascript");
  server.set_file_extension_and_mimetype_mapping("bgivg", "application/octet-stream");
  if (!server.set_mount_point("/", folder.string())) {
    throw FileError(folder.string() + ": not a folder");
  }
  // Loopback only: the page and its data are for this machine.
  const int bound = port == 0 ? server.bind_to_any_port("127.0.0.1")
                              : (server.bind_to_port("127.0.0.1", int(port)) ? int(port) : -1);
  if (bound < 0) throw FileError("cannot listen on 127.0.0.1:" + std::to_string(port));
  running_server = &server;
  std::signal(SIGINT, stop_on_signal);
  std::signal(SIGTERM, stop_on_signal);
  std::printf("serving %s at http://127.0.0.1:%d/ (Ctrl-C stops)\n", folder.string().c_str(),
              bound);
  std::fflush(stdout);
  server.listen_after_bind();
  running_server = nullptr;
  return kExitOk;
}

#else

int run_serve_command(const std::vector<std::string>&) {
  throw UsageError(
      "this bakegi was built without cpp-httplib (Debian 12's libcpp-httplib-dev), "
      "so it cannot serve; open the exported folder's index.html instead");
}

#endif

}  // namespace bakegi::cli
