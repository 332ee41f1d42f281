#pragma once

// Headless chromium for the viewer's browser tests: run it on a page (--dump-dom or
// --screenshot), read the report of the page's test driver, decode a PNG screenshot (zlib).

#include <unistd.h>
#include <zlib.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace idto::test {

namespace fs = std::filesystem;

/// The chromium executable ($IDTO_CHROMIUM, else /usr/bin/chromium), or "" when there is none.
inline std::string ChromiumPath() {
  const char* env = std::getenv("IDTO_CHROMIUM");
  const std::string path = env != nullptr && env[0] != '\0' ? env : "/usr/bin/chromium";
  return ::access(path.c_str(), X_OK) == 0 ? path : std::string();
}

struct ChromiumRun {
  int status{-1};
  std::string out;  // stdout (the DOM for --dump-dom)
  std::string err;  // stderr (chromium's log, with the page's console messages)
  double seconds{0.0};
  /// The page's console messages in chromium's log ("...:CONSOLE..." lines).
  std::vector<std::string> ConsoleLines() const {
    std::vector<std::string> lines;
    std::istringstream in(err);
    for (std::string line; std::getline(in, line);) {
      if (line.find(":CONSOLE") != std::string::npos) lines.push_back(line);
    }
    return lines;
  }
};

inline std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::string ShellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

/// Percent-encodes everything but letters and digits (for a URL fragment).
inline std::string UrlEncode(const std::string& s) {
  std::string out;
  for (unsigned char c : s) {
    if (std::isalnum(c)) {
      out += static_cast<char>(c);
    } else {
      char buffer[4];
      std::snprintf(buffer, sizeof(buffer), "%%%02X", c);
      out += buffer;
    }
  }
  return out;
}

/// Runs headless chromium (software WebGL, a fresh profile in `work`, a 1000 x 700 window) with
/// `args` appended, at most `timeout_s` seconds (generous: on a loaded shared machine a launch
/// has taken 90 s; idle, a few seconds).
inline ChromiumRun RunChromium(const std::string& chromium, const std::vector<std::string>& args,
                               const fs::path& work, int timeout_s = 300) {
  const std::vector<std::string> base = {"--headless",
                                         "--no-sandbox",
                                         "--use-angle=swiftshader",
                                         "--enable-unsafe-swiftshader",
                                         "--enable-logging=stderr",
                                         "--v=0",
                                         "--user-data-dir=" + (work / "profile").string(),
                                         "--no-first-run",
                                         "--disable-extensions",
                                         "--disable-background-networking",
                                         "--disable-component-update",
                                         "--disable-sync",
                                         "--mute-audio",
                                         "--hide-scrollbars",
                                         "--window-size=1000,700"};
  std::string command = "timeout " + std::to_string(timeout_s) + " " + ShellQuote(chromium);
  for (const std::string& a : base) command += " " + ShellQuote(a);
  for (const std::string& a : args) command += " " + ShellQuote(a);
  const fs::path out = work / "chromium.out";
  const fs::path err = work / "chromium.err";
  command += " >" + ShellQuote(out.string()) + " 2>" + ShellQuote(err.string()) + " </dev/null";
  const auto start = std::chrono::steady_clock::now();
  ChromiumRun run;
  run.status = std::system(command.c_str());
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.out = ReadText(out);
  run.err = ReadText(err);
  return run;
}

/// The text of the page's test-driver report (#idto-test-output) in a dumped DOM, unescaped.
inline std::string TestReport(const std::string& dom) {
  const std::string begin = "<pre id=\"idto-test-output\">";
  const std::size_t a = dom.find(begin);
  if (a == std::string::npos) return {};
  const std::size_t b = dom.find("</pre>", a);
  std::string text = dom.substr(a + begin.size(), b - a - begin.size());
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    bool replaced = false;
    for (const auto& [entity, c] : {std::pair<const char*, char>{"&quot;", '"'},
                                    {"&amp;", '&'},
                                    {"&lt;", '<'},
                                    {"&gt;", '>'},
                                    {"&#39;", '\''},
                                    {"&nbsp;", ' '}}) {
      const std::string e(entity);
      if (text.compare(i, e.size(), e) == 0) {
        out += c;
        i += e.size() - 1;
        replaced = true;
        break;
      }
    }
    if (!replaced) out += text[i];
  }
  return out;
}

/// An 8-bit RGB or RGBA image, rows top to bottom.
struct Image {
  int width{0}, height{0}, channels{0};
  std::vector<std::uint8_t> pixels;
};

/// Decodes a non-interlaced 8-bit RGB(A) PNG (what chromium's --screenshot writes).
inline Image DecodePng(const std::string& data) {
  const auto be32 = [&](std::size_t at) {
    return (std::uint32_t(std::uint8_t(data[at])) << 24) |
           (std::uint32_t(std::uint8_t(data[at + 1])) << 16) |
           (std::uint32_t(std::uint8_t(data[at + 2])) << 8) | std::uint8_t(data[at + 3]);
  };
  if (data.size() < 8 || data.compare(1, 3, "PNG") != 0) throw std::runtime_error("not a PNG");
  Image image;
  std::string idat;
  for (std::size_t at = 8; at + 8 <= data.size();) {
    const std::uint32_t length = be32(at);
    const std::string type = data.substr(at + 4, 4);
    if (type == "IHDR") {
      image.width = static_cast<int>(be32(at + 8));
      image.height = static_cast<int>(be32(at + 12));
      const int depth = std::uint8_t(data[at + 16]), color = std::uint8_t(data[at + 17]);
      if (depth != 8 || (color != 2 && color != 6) || data[at + 20] != 0) {
        throw std::runtime_error("unsupported PNG format");
      }
      image.channels = color == 6 ? 4 : 3;
    } else if (type == "IDAT") {
      idat += data.substr(at + 8, length);
    }
    at += 12 + length;
  }
  const std::size_t stride = static_cast<std::size_t>(image.width) * image.channels;
  std::vector<std::uint8_t> raw((stride + 1) * image.height);
  uLongf size = raw.size();
  if (uncompress(raw.data(), &size, reinterpret_cast<const Bytef*>(idat.data()), idat.size()) !=
          Z_OK ||
      size != raw.size()) {
    throw std::runtime_error("corrupt PNG data");
  }
  image.pixels.resize(stride * image.height);
  const int bpp = image.channels;
  for (int y = 0; y < image.height; ++y) {
    const std::uint8_t filter = raw[y * (stride + 1)];
    const std::uint8_t* in = &raw[y * (stride + 1) + 1];
    std::uint8_t* row = &image.pixels[y * stride];
    const std::uint8_t* up = y > 0 ? &image.pixels[(y - 1) * stride] : nullptr;
    for (std::size_t x = 0; x < stride; ++x) {
      const int a = x >= static_cast<std::size_t>(bpp) ? row[x - bpp] : 0;
      const int b = up ? up[x] : 0;
      const int c = up && x >= static_cast<std::size_t>(bpp) ? up[x - bpp] : 0;
      int predictor = 0;
      if (filter == 1) predictor = a;
      if (filter == 2) predictor = b;
      if (filter == 3) predictor = (a + b) / 2;
      if (filter == 4) {
        const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
        predictor = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      row[x] = static_cast<std::uint8_t>(in[x] + predictor);
    }
  }
  return image;
}

}  // namespace idto::test
