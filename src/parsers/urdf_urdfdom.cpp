// urdfdom as a cross-check of idto's own URDF reading.
//
// urdfdom stops reading a link at the first element it cannot parse and reports through
// console_bridge, so it cannot be the reader of record (its losses would be silent). It is run on
// the same text, with its messages captured, and when it accepts the file, idto must have kept at
// least what urdfdom found.

#include <mutex>
#include <string>
#include <vector>

#include <console_bridge/console.h>
#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include "idto/core/errors.hpp"
#include "urdf_document.hpp"

namespace idto {
namespace urdf_internal {
namespace {

/// Swallows urdfdom's messages while a parse runs. It is installed as console_bridge's output
/// handler for the duration of one parse (under a mutex: the handler is global). The object is
/// never destroyed, so console_bridge's "previous handler" pointer can never dangle; outside a
/// parse it forwards to the handler that was current before the last parse.
class CaptureHandler final : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char* filename,
           int line) override {
    if (capturing_) return;
    if (forward_ != nullptr && forward_ != this) forward_->log(text, level, filename, line);
  }

  void Begin() {
    forward_ = console_bridge::getOutputHandler();
    saved_level_ = console_bridge::getLogLevel();
    capturing_ = true;
    console_bridge::useOutputHandler(this);
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_WARN);
  }

  void End() {
    console_bridge::setLogLevel(saved_level_);
    console_bridge::restorePreviousOutputHandler();
    capturing_ = false;
  }

 private:
  bool capturing_{false};
  console_bridge::OutputHandler* forward_{nullptr};
  console_bridge::LogLevel saved_level_{console_bridge::CONSOLE_BRIDGE_LOG_WARN};
};

/// urdfdom's model of `xml`, or null when urdfdom refuses it.
urdf::ModelInterfaceSharedPtr ParseWithUrdfdom(const std::string& xml) {
  static std::mutex mutex;
  static CaptureHandler* const handler = new CaptureHandler();  // never destroyed, see above
  std::lock_guard<std::mutex> lock(mutex);
  handler->Begin();
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(xml);
  } catch (const std::exception&) {
    model = nullptr;
  }
  handler->End();
  return model;
}

}  // namespace

void CrossCheckWithUrdfdom(const std::string& xml, const UrdfDocument& doc,
                           const UrdfReporter& reporter) {
  const urdf::ModelInterfaceSharedPtr model = ParseWithUrdfdom(xml);
  if (model == nullptr) return;
  auto mismatch = [&](const std::string& element, const std::string& what, size_t urdfdom,
                      size_t idto) {
    reporter.Error(element, "urdfdom found " + std::to_string(urdfdom) + " " + what +
                                ", idto read " + std::to_string(idto) +
                                " (an idto bug: please report it with this file)");
  };
  if (model->joints_.size() > doc.joints.size()) {
    mismatch("robot", "joints", model->joints_.size(), doc.joints.size());
  }
  for (const auto& [name, link] : model->links_) {
    if (link == nullptr) continue;
    if (doc.link_index.count(name) == 0) mismatch(LinkElement(name), "link", 1, 0);
    size_t shapes = 0;
    for (const urdf::CollisionSharedPtr& c : link->collision_array) {
      if (c != nullptr && c->geometry != nullptr) ++shapes;
    }
    const size_t kept = doc.link(name).collisions.size();
    if (shapes > kept) mismatch(LinkElement(name), "collision shapes", shapes, kept);
  }
}

}  // namespace urdf_internal
}  // namespace idto
