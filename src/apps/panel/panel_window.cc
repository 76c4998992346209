#include "src/apps/panel/panel_window.h"

#include <GLFW/glfw3.h>  // includes GL/gl.h (glReadPixels, glFinish, glClear)
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <future>
#include <stdexcept>
#include <utility>

#include "geometry/live_boundary.h"
#include "haptics/rendering/renderer_factory.h"
#include "src/apps/panel/direct_draw.h"
#include "src/apps/panel/robot_view.h"
#include "src/core/pose.h"
#include "src/core/units.h"
#include "src/panel/panel_controller.h"

namespace robossis::apps {
namespace {

// [assumed] display budgets for the software renderer: triangles per bone fragment and edges of the slice drawn (an
// edge is two triangles, and the rasteriser's cost grows with the triangles: see the panel section of BENCHMARKS.md).
constexpr std::size_t kMaxFragmentTriangles = 2500;
constexpr std::size_t kMaxSliceEdges = 3000;
// The panel's fixed windows draw no background of their own: on the software renderer a window background is a
// textured, blended quad over most of the screen (measured: the larger part of a 1920x1080 frame's rasterisation),
// while glClear, which paints the same colour, is a memset.
constexpr ImGuiWindowFlags kFixedWindow =
    ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoBackground;
// The background colour glClear paints, the 3-D view's too: the view is told apart by a frame, not by a fill of its
// own (a scissored glClear is a drawn quad on Mesa's software renderer, measured at 3.8 ms of a 1920x1080 frame's
// rasteriser time, where the whole-window clear is 2.8 ms).
constexpr ImU32 kViewFrame = IM_COL32(70, 78, 96, 255);
// [assumed] plot resolution: one point per this many pixel columns (a 540 px plot shows 270 points of its 10 s).
constexpr float kPlotPixelsPerPoint = 2.0f;
// [assumed] regenerate the drawn workspace slice when the orientation moved by more than this.
constexpr double kSliceRefreshRad = 0.5 * kDegToRad;
// [assumed] the drawn slice is coarser than the haptic one (geometry's 4 mm): it is a picture, not a wall.
constexpr double kSliceDrawResolutionM = 0.010;

struct GlfwSession {
  GLFWwindow* window = nullptr;
  GlfwSession(int width, int height, bool vsync) {
    if (!glfwInit()) throw std::runtime_error("panel: cannot initialise GLFW (is there a display? try xvfb-run -a)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    window = glfwCreateWindow(width, height, "Robossis control panel", nullptr, nullptr);
    if (!window) {
      glfwTerminate();
      throw std::runtime_error("panel: cannot open an OpenGL 3.3 window");
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(vsync ? 1 : 0);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini next to the caller: every start looks the same
    ImGui::StyleColorsDark();
    // The title bars keep their titles but lose their filled strips: glClear paints the panel's background anyway,
    // and on the software renderer a filled strip is ~36k blended pixels per frame at 1920 px (ImGui skips a fill
    // whose alpha is 0).
    for (const ImGuiCol bar : {ImGuiCol_TitleBg, ImGuiCol_TitleBgActive, ImGuiCol_TitleBgCollapsed})
      ImGui::GetStyle().Colors[bar] = ImVec4(0, 0, 0, 0);
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    ImGui_ImplOpenGL3_Init("#version 330");
  }
  ~GlfwSession() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window);
    glfwTerminate();
  }
  GlfwSession(const GlfwSession&) = delete;
  GlfwSession& operator=(const GlfwSession&) = delete;
};

// A titled separator (ImGui 1.86 has no SeparatorText).
void Section(const char* title) {
  ImGui::Spacing();
  ImGui::TextColored(ImVec4(0.6f, 0.8f, 1.0f, 1), "%s", title);
  ImGui::Separator();
}

ImVec4 StateColor(teleop::OperatingState state) {
  using teleop::OperatingState;
  switch (state) {
    case OperatingState::kEnabled: return ImVec4(0.3f, 0.9f, 0.4f, 1);
    case OperatingState::kClutched: return ImVec4(0.4f, 0.7f, 1.0f, 1);
    case OperatingState::kReady: return ImVec4(0.9f, 0.9f, 0.5f, 1);
    case OperatingState::kHoming: return ImVec4(0.9f, 0.7f, 0.3f, 1);
    case OperatingState::kFault:
    case OperatingState::kEStop: return ImVec4(1.0f, 0.3f, 0.3f, 1);
    default: return ImVec4(0.7f, 0.7f, 0.7f, 1);
  }
}

// A time series: the signals `columns` of the buffer over its window, each in its colour, with a legend.
// What the frame's plots and 3-D view draw through OpenGL directly (direct_draw.h), refilled every frame.
struct DirectLayers {
  DirectRenderer renderer;
  RobotViewBatches view;
  std::array<LineImage, 3> plots;  // position, orientation, force (line_image.h)
  std::array<ImageTexture, 3> plot_textures;
  // The lines rasterised into images and the triangles drawn directly.
  long primitive_count() const {
    std::size_t n = view.slice.line_count() + view.bone.triangle_count();
    for (const LineImage& plot : plots) n += plot.line_count();
    return static_cast<long>(n);
  }
};

template <std::size_t N>
void TimePlot(const char* title, const panel::PlotBuffer<N>& buffer, std::initializer_list<int> columns,
              std::initializer_list<const char*> names, std::initializer_list<ImU32> colors, ImVec2 size,
              DirectRenderer& gl, LineImage& image, ImageTexture& texture) {
  ImGui::TextUnformatted(title);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImVec2 o = ImGui::GetCursorScreenPos();
  // The plot's background is the panel's (glClear's), its box a 1 px frame: only the bands of rows its lines
  // light are drawn (ImageTexture::Draw with only_lit_rows).
  image.Reset(o, ImVec2(o.x + size.x, o.y + size.y), kPanelBackground);
  ImGui::Dummy(size);
  if (buffer.size() < 2) {
    draw->AddRect(o, ImVec2(o.x + size.x, o.y + size.y), kViewFrame);
    return;
  }
  float lo = 1e30f, hi = -1e30f;
  for (std::size_t i = 0; i < buffer.size(); ++i)
    for (int c : columns) lo = std::min(lo, buffer.values(i)[c]), hi = std::max(hi, buffer.values(i)[c]);
  if (hi - lo < 1e-3f) lo -= 0.5f, hi += 0.5f;
  const double t0 = buffer.time_s(0), t1 = buffer.time_s(buffer.size() - 1);
  const double span = std::max(1e-6, t1 - t0);
  // Each signal is one polyline of at most one point per kPlotPixelsPerPoint pixel columns (decimated by a
  // stride; the newest sample always ends it), 1 px lines rasterised into the plot's image (line_image.h), drawn
  // as one quad: the software renderer's cost is per primitive, and ImGui's polyline of N points was 2(N-1)
  // textured triangles.
  const std::size_t max_points = std::max<std::size_t>(2, static_cast<std::size_t>(size.x / kPlotPixelsPerPoint));
  const std::size_t stride = std::max<std::size_t>(1, (buffer.size() + max_points - 1) / max_points);
  static thread_local std::vector<ImVec2> points;  // the window thread's scratch, reused every frame
  auto color = colors.begin();
  for (int c : columns) {
    points.clear();
    for (std::size_t i = 0; i < buffer.size(); i += stride) {
      const std::size_t k = std::min(i + stride >= buffer.size() ? buffer.size() - 1 : i, buffer.size() - 1);
      points.emplace_back(o.x + static_cast<float>((buffer.time_s(k) - t0) / span) * size.x,
                          o.y + size.y - (buffer.values(k)[c] - lo) / (hi - lo) * (size.y - 4) - 2);
    }
    image.AddPolyline(points.data(), static_cast<int>(points.size()), *color);
    ++color;
  }
  texture.Draw(draw, gl, image, /*only_lit_rows=*/true);
  draw->AddRect(o, ImVec2(o.x + size.x, o.y + size.y), kViewFrame);  // over the image's edge columns
  char range[64];
  std::snprintf(range, sizeof range, "%.2f .. %.2f", lo, hi);
  draw->AddText(ImVec2(o.x + 4, o.y + 2), IM_COL32(200, 200, 200, 255), range);
  color = colors.begin();
  float x = o.x + 120;
  for (const char* name : names) {
    draw->AddText(ImVec2(x, o.y + 2), *color++, name);
    x += ImGui::CalcTextSize(name).x + 12;
  }
}

void Gauge(const panel::JointGauge& gauge) {
  const float fraction = static_cast<float>(gauge.fraction());
  const bool tight = gauge.margin < 0.1 * (gauge.upper - gauge.lower);
  ImGui::PushStyleColor(ImGuiCol_PlotHistogram, gauge.margin < 0    ? ImVec4(1, 0.2f, 0.2f, 1)
                                                : tight ? ImVec4(0.95f, 0.65f, 0.2f, 1)
                                                        : ImVec4(0.3f, 0.7f, 0.4f, 1));
  char overlay[96];
  std::snprintf(overlay, sizeof overlay, "%.2f %s  (margin %.2f)", gauge.value, gauge.unit, gauge.margin);
  ImGui::ProgressBar(fraction, ImVec2(230, 0), overlay);
  ImGui::PopStyleColor();
  ImGui::SameLine();
  ImGui::Text("%s [%.0f, %.0f]", gauge.label.c_str(), gauge.lower, gauge.upper);
}

class SliceRefresher {
 public:
  SliceRefresher(const robot::RsrModel& rsr, const robot::Sigma7Model& hc) {
    geometry::LiveBoundaryOptions options;
    options.dexterous_resolution_m = kSliceDrawResolutionM;
    boundary_ = std::make_unique<geometry::LiveBoundary>(rsr, hc, options);
  }
  // Starts a regeneration at `rpy` when the drawn slice is too far from it; takes a finished one into `edges` and
  // counts it in `generation`.
  void Poll(const Eigen::Vector3d& rpy, std::vector<std::array<Eigen::Vector3d, 2>>& edges, std::uint64_t& generation) {
    if (pending_.valid() && pending_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
      edges = pending_.get();
      ++generation;
    }
    if (!pending_.valid() && (!generated_ || (rpy - generated_rpy_).cwiseAbs().maxCoeff() > kSliceRefreshRad)) {
      generated_ = true;
      generated_rpy_ = rpy;
      geometry::LiveBoundary* boundary = boundary_.get();
      pending_ = std::async(std::launch::async, [boundary, rpy] {
        std::vector<std::array<Eigen::Vector3d, 2>> result;
        std::unique_ptr<geometry::LiveSlice> slice = boundary->Generate(geometry::SliceKind::kRsrDexterous, rpy);
        if (slice && slice->field)
          result = MeshEdges(slice->field->mesh().vertices, slice->field->mesh().triangles, kMaxSliceEdges);
        return result;
      });
    }
  }
  ~SliceRefresher() {
    if (pending_.valid()) pending_.wait();
  }

 private:
  std::unique_ptr<geometry::LiveBoundary> boundary_;
  std::future<std::vector<std::array<Eigen::Vector3d, 2>>> pending_;
  bool generated_ = false;
  Eigen::Vector3d generated_rpy_ = Eigen::Vector3d::Zero();
};

void DrawTopBar(panel::PanelController& panel, float width) {
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(width, 64));
  ImGui::Begin("State", nullptr, ImGuiWindowFlags_NoDecoration | kFixedWindow);
  ImGui::PushStyleColor(ImGuiCol_Button, ImVec4(0.85f, 0.1f, 0.1f, 1));
  ImGui::PushStyleColor(ImGuiCol_ButtonHovered, ImVec4(1.0f, 0.2f, 0.2f, 1));
  if (ImGui::Button("E-STOP", ImVec2(150, 48))) panel.Click("estop");
  ImGui::PopStyleColor(2);
  ImGui::SameLine();
  const panel::PanelViewModel& view = panel.view();
  ImGui::BeginGroup();
  ImGui::Text("state:");
  ImGui::SameLine();
  ImGui::TextColored(StateColor(view.state), "%s", view.has_status ? view.state_name.c_str() : "no status");
  ImGui::Text("last fault: %s", panel.last_fault().empty() ? "none" : panel.last_fault().c_str());
  ImGui::EndGroup();
  ImGui::SameLine(520);
  if (ImGui::Button("Reset", ImVec2(90, 48))) panel.Click("reset");
  ImGui::SameLine();
  ImGui::BeginDisabled(view.has_status && !view.home_allowed);
  if (ImGui::Button("Home", ImVec2(90, 48))) panel.Click("home");
  ImGui::EndDisabled();
  ImGui::SameLine();
  if (ImGui::Button("Enable", ImVec2(90, 48))) panel.Click("enable");
  ImGui::SameLine();
  if (ImGui::Button("Disable", ImVec2(90, 48))) panel.Click("disable");
  ImGui::SameLine();
  if (!panel.message().empty()) ImGui::TextColored(ImVec4(1, 0.6f, 0.3f, 1), "%s", panel.message().c_str());
  ImGui::End();
}

void DrawControls(panel::PanelController& panel, float height) {
  ImGui::SetNextWindowPos(ImVec2(0, 64));
  ImGui::SetNextWindowSize(ImVec2(380, height - 64));
  ImGui::Begin("Controls", nullptr, kFixedWindow);
  panel::JogForm& form = panel.jog_form();
  Section("Manual jog (eq. 9)");
  static const char* kAxes[] = {"x", "y", "z", "roll", "pitch", "yaw"};
  int axis = static_cast<int>(form.axis);
  if (ImGui::Combo("axis", &axis, kAxes, 6)) form.axis = static_cast<panel::JogAxis>(axis);
  const bool rotational = panel::IsRotational(form.axis);
  ImGui::InputDouble(rotational ? "amount (deg)" : "amount (mm)", &form.amount, 0.5, 5, "%.3f");
  int timing = form.timing == panel::JogTiming::kDuration ? 0 : 1;
  ImGui::RadioButton("time interval", &timing, 0);
  ImGui::SameLine();
  ImGui::RadioButton("speed", &timing, 1);
  form.timing = timing == 0 ? panel::JogTiming::kDuration : panel::JogTiming::kSpeed;
  if (form.timing == panel::JogTiming::kDuration)
    ImGui::InputDouble("interval (s)", &form.duration_s, 0.5, 2, "%.2f");
  else
    ImGui::InputDouble(rotational ? "peak speed (deg/s)" : "peak speed (mm/s)", &form.speed, 0.1, 1, "%.3f");
  if (ImGui::Button("Preview", ImVec2(100, 0))) panel.Click("jog.preview");
  ImGui::SameLine();
  if (ImGui::Button("Go", ImVec2(100, 0))) panel.Click("jog.go");
  ImGui::SameLine();
  if (ImGui::Button("Stop", ImVec2(100, 0))) panel.Click("jog.stop");
  if (const auto& verdict = panel.last_verdict()) {
    const Vector6d end = MmDegFromPose(verdict->X_FM_end);
    if (verdict->accepted)
      ImGui::TextColored(ImVec4(0.4f, 0.9f, 0.5f, 1), "inside the workspace: %.2f s, tightest margin %.2f %s",
                         verdict->duration_s,
                         verdict->tightest.margin * (verdict->tightest.joint == robot::RsrJointKind::kStroke ? 1e3 : kRadToDeg),
                         verdict->tightest.joint == robot::RsrJointKind::kStroke ? "mm" : "deg");
    else
      ImGui::TextWrapped("refused: %s", verdict->reason.c_str());
    ImGui::Text("end: %.1f %.1f %.1f mm  %.2f %.2f %.2f deg", end[0], end[1], end[2], end[3], end[4], end[5]);
  }

  Section("Haptic mode");
  const panel::HapticModeModel& haptic = panel.haptic();
  if (ImGui::Button(haptic.enabled() ? "Haptic off" : "Haptic on", ImVec2(110, 0)))
    panel.Click(haptic.enabled() ? "haptic.off" : "haptic.on");
  ImGui::SameLine();
  if (ImGui::Button(haptic.clutched() ? "Engage" : "Clutch", ImVec2(110, 0)))
    panel.Click(haptic.clutched() ? "haptic.unclutch" : "haptic.clutch");
  int method = haptic.method_index();
  std::vector<const char*> names;
  for (const std::string& name : haptic.methods()) names.push_back(name.c_str());
  if (ImGui::Combo("rendering", &method, names.data(), static_cast<int>(names.size())))
    panel.SetMethod(haptic.methods()[method]);
  int preset = haptic.cap_preset() == panel::SpeedCapPreset::kClinical ? 0 : 1;
  const int before = preset;
  ImGui::RadioButton("clinical", &preset, 0);
  ImGui::SameLine();
  ImGui::RadioButton("demonstration", &preset, 1);
  if (preset != before) panel.SetCapPreset(preset == 0 ? panel::SpeedCapPreset::kClinical : panel::SpeedCapPreset::kDemonstration);
  const panel::SpeedCapValues caps = haptic.caps();
  ImGui::Text("caps: %.1f mm/s, %.2f deg/s%s", MToMm(caps.max_linear_speed_m_s), RadToDeg(caps.max_angular_speed_rad_s),
              haptic.clutched() ? "" : "  (change while clutched)");

  Section("Health");
  const panel::LoopHealth& health = panel.health();
  ImGui::Text("loop %.0f Hz, ticks %llu", health.period_s > 0 ? 1 / health.period_s : 0.0,
              static_cast<unsigned long long>(health.ticks));
  ImGui::Text("period jitter: last %.3f ms, max %.3f ms", 1e3 * health.last_jitter_s, 1e3 * health.max_jitter_s);
  const auto u = [](std::uint64_t n) { return static_cast<unsigned long long>(n); };
  const rt::LoopCounts& f = health.follower_loop;
  const rt::LoopCounts& l = health.leader_loop;
  ImGui::Text("overruns: %llu (late wake-up %llu, long tick %llu)   watchdog holds: %llu", u(f.overruns),
              u(f.overruns_late_wake), u(f.overruns_long_tick), u(health.watchdog_holds));
  ImGui::Text("leader overruns: %llu (late wake-up %llu, long tick %llu)", u(l.overruns), u(l.overruns_late_wake),
              u(l.overruns_long_tick));
  if (health.setpoint_age_s < 0)
    ImGui::Text("set-point age: none yet");
  else
    ImGui::Text("set-point age: %.3f s", health.setpoint_age_s);
  ImGui::End();
}

void DrawNumbers(panel::PanelController& panel, DirectLayers& direct, float x, float width, float height) {
  ImGui::SetNextWindowPos(ImVec2(x, 64));
  ImGui::SetNextWindowSize(ImVec2(width, height - 64));
  ImGui::Begin("Pose and joints", nullptr, kFixedWindow);
  const panel::PanelViewModel& view = panel.view();
  Section("Pose of the moving ring");
  ImGui::Text("x %8.2f  y %8.2f  z %8.2f mm", view.pose_mm_deg[0], view.pose_mm_deg[1], view.pose_mm_deg[2]);
  ImGui::Text("roll %6.2f  pitch %6.2f  yaw %6.2f deg", view.pose_mm_deg[3], view.pose_mm_deg[4], view.pose_mm_deg[5]);
  Section("Joints between their limits");
  for (const panel::JointGauge& gauge : view.gauges) Gauge(gauge);
  Section("Plots");
  const ImVec2 plot(width - 20, 90);
  const auto& pose = panel.pose_plot();
  TimePlot("position (mm): commanded vs measured", pose, {0, 1, 2, 6, 7, 8}, {"cmd x", "y", "z", "meas x", "y", "z"},
           {IM_COL32(255, 120, 120, 255), IM_COL32(120, 255, 120, 255), IM_COL32(120, 160, 255, 255),
            IM_COL32(180, 60, 60, 255), IM_COL32(60, 170, 60, 255), IM_COL32(60, 90, 200, 255)},
           plot, direct.renderer, direct.plots[0], direct.plot_textures[0]);
  TimePlot("orientation (deg): commanded vs measured", pose, {3, 4, 5, 9, 10, 11},
           {"cmd roll", "pitch", "yaw", "meas roll", "pitch", "yaw"},
           {IM_COL32(255, 120, 120, 255), IM_COL32(120, 255, 120, 255), IM_COL32(120, 160, 255, 255),
            IM_COL32(180, 60, 60, 255), IM_COL32(60, 170, 60, 255), IM_COL32(60, 90, 200, 255)},
           plot, direct.renderer, direct.plots[1], direct.plot_textures[1]);
  TimePlot("force on the hand (N)", panel.wrench_plot(), {0, 1, 2}, {"Fx", "Fy", "Fz"},
           {IM_COL32(255, 120, 120, 255), IM_COL32(120, 255, 120, 255), IM_COL32(120, 160, 255, 255)}, plot,
           direct.renderer, direct.plots[2], direct.plot_textures[2]);
  ImGui::End();
}

void DrawRobotWindow(panel::PanelController& panel, const RobotScene& scene, DirectLayers& direct, float x,
                     float width, float height) {
  ImGui::SetNextWindowPos(ImVec2(x, 64));
  ImGui::SetNextWindowSize(ImVec2(width, height - 64));
  ImGui::Begin("Robot", nullptr, kFixedWindow);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const ImVec2 size = ImGui::GetContentRegionAvail();
  ImGui::InvisibleButton("view", size);
  panel::Camera& camera = panel.camera();
  if (ImGui::IsItemActive() && ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {  // orbit
    const ImVec2 delta = ImGui::GetIO().MouseDelta;
    camera.azimuth_deg -= 0.3 * delta.x;
    camera.elevation_deg = std::clamp(camera.elevation_deg + 0.3 * delta.y, -89.0, 89.0);
  }
  if (ImGui::IsItemHovered() && ImGui::GetIO().MouseWheel != 0)  // zoom
    camera.distance_mm = std::clamp(camera.distance_mm * std::pow(0.9, ImGui::GetIO().MouseWheel), 200.0, 5000.0);
  DrawRobotView(ImGui::GetWindowDrawList(), direct.renderer, direct.view, origin, size, camera, panel.model(),
                panel.view().X_FM, panel.commanded_pose(), scene, panel.wrench());
  ImGui::GetWindowDrawList()->AddRect(origin, ImVec2(origin.x + size.x, origin.y + size.y), kViewFrame);
  ImGui::GetWindowDrawList()->AddText(ImVec2(origin.x + 8, origin.y + 8), IM_COL32(200, 200, 200, 255),
                                      "drag: orbit   wheel: zoom   cross: commanded centre   blue: workspace slice");
  ImGui::End();
}

panel::HapticModeModel InitialHapticMode(const PanelModels& models) {
  panel::HapticModeModel mode(haptics::KnownMethods(), models.demonstration_caps);
  std::string reason;
  if (!models.default_method.empty() && !mode.SetMethod(models.default_method, reason))
    throw std::runtime_error("panel: default rendering method: " + reason);
  return mode;
}

double Percentile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  const std::size_t k = std::min(values.size() - 1, static_cast<std::size_t>(q * (values.size() - 1) + 0.5));
  std::nth_element(values.begin(), values.begin() + static_cast<long>(k), values.end());
  return values[k];
}

}  // namespace

void SaveFramebufferPng(const OutputPolicy& output, const std::string& option, const std::string& path, int width,
                        int height) {
  cv::Mat rgb(height, width, CV_8UC3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data);
  cv::Mat bgr(height, width, CV_8UC3);
  for (int r = 0; r < height; ++r) {  // OpenGL's rows start at the bottom; PNG's at the top. RGB → BGR.
    const unsigned char* src = rgb.ptr<unsigned char>(height - 1 - r);
    unsigned char* dst = bgr.ptr<unsigned char>(r);
    for (int c = 0; c < width; ++c) {
      dst[3 * c + 0] = src[3 * c + 2];
      dst[3 * c + 1] = src[3 * c + 1];
      dst[3 * c + 2] = src[3 * c + 0];
    }
  }
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", bgr, png)) throw std::runtime_error(option + ": " + path + ": cannot encode the PNG");
  WriteOutputFile(output, path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()), option);
}

struct PanelWindow::Impl {
  Impl(panel::PanelBackend& backend, const PanelModels& models, const PanelWindowOptions& options)
      : options(options),
        controller(backend, models.rsr, models.config, InitialHapticMode(models)),
        session(options.width_px, options.height_px, options.vsync),
        script(options.script),
        start(std::chrono::steady_clock::now()) {
    if (models.fragments) {
      scene.proximal_F = ReduceForDrawing(models.fragments->proximal_F.vertices,
                                          models.fragments->proximal_F.triangles, kMaxFragmentTriangles);
      scene.distal_M = ReduceForDrawing(models.fragments->distal_M.vertices, models.fragments->distal_M.triangles,
                                        kMaxFragmentTriangles);
    }
    if (options.workspace_slice) slices = std::make_unique<SliceRefresher>(models.rsr, models.hc);
  }
  double SecondsSinceStart() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  PanelWindowOptions options;
  panel::PanelController controller;
  RobotScene scene;
  std::unique_ptr<SliceRefresher> slices;
  GlfwSession session;
  DirectLayers direct;  // after the session: its GL objects go before the context
  panel::ScriptPlayer script;
  std::chrono::steady_clock::time_point start;
  std::vector<double> frame_ms;
  std::array<std::vector<double>, kFramePhases> phase_ms;  // where each frame's time went (FramePhase)
  std::vector<std::string> screenshots;
  long frames = 0;
  double max_hand_force_n = 0;
  long triangles = 0;
  long direct_primitives = 0;
  bool done = false;
};

PanelWindow::PanelWindow(panel::PanelBackend& backend, const PanelModels& models, const PanelWindowOptions& options)
    : impl_(std::make_unique<Impl>(backend, models, options)) {}

PanelWindow::~PanelWindow() = default;

bool PanelWindow::Frame() {
  Impl& m = *impl_;
  if (m.done || glfwWindowShouldClose(m.session.window)) return false;
  const auto frame_start = std::chrono::steady_clock::now();
  glfwPollEvents();
  const double now_s = m.SecondsSinceStart();
  bool quit = false;
  std::vector<std::pair<std::string, std::string>> screenshots_due;  // (what named it, path)
  while (const panel::ScriptAction* action = m.script.NextDue(now_s)) {
    try {
      if (action->verb == panel::ScriptVerb::kWait) {
        // Checked on the previous frame's view (Update below): a command clicked in this frame has not been seen.
        if (m.controller.ScriptConditionHolds(*action)) {
          m.script.Satisfied(now_s);
          continue;
        }
        if (m.script.WaitingS(now_s) > action->timeout_s) {
          char timeout[32];
          std::snprintf(timeout, sizeof timeout, "%g s", action->timeout_s);
          throw std::invalid_argument("wait " + action->target + (action->value.empty() ? "" : " " + action->value) +
                                      ": not reached within " + timeout + " (state " +
                                      m.controller.view().state_name + ", message '" + m.controller.message() + "')");
        }
        break;  // the actions after the wait stay back until a later frame
      }
      switch (action->verb) {
        case panel::ScriptVerb::kClick: m.controller.Click(action->target); break;
        case panel::ScriptVerb::kSet: m.controller.Set(action->target, action->value); break;
        case panel::ScriptVerb::kScreenshot:
          screenshots_due.emplace_back("--script line " + std::to_string(action->line) + " screenshot",
                                       action->target);
          break;
        case panel::ScriptVerb::kQuit: quit = true; break;
        case panel::ScriptVerb::kWait: break;  // handled above
      }
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("--script line " + std::to_string(action->line) + ": " + e.what());
    }
  }
  m.controller.Update(now_s);
  const auto update_end = std::chrono::steady_clock::now();
  const panel::HandWrench& wrench = m.controller.wrench();
  m.max_hand_force_n = std::max(m.max_hand_force_n, std::hypot(wrench.force_n[0], wrench.force_n[1], wrench.force_n[2]));
  if (m.slices) m.slices->Poll(RpyFromRotation(m.controller.view().X_FM.linear()), m.scene.slice_edges_F,
                                 m.scene.slice_generation);

  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  int width = 0, height = 0;
  glfwGetFramebufferSize(m.session.window, &width, &height);
  const float w = static_cast<float>(width), h = static_cast<float>(height);
  const float numbers_width = std::min(560.0f, 0.33f * w);
  DrawTopBar(m.controller, w);
  DrawControls(m.controller, h);
  DrawRobotWindow(m.controller, m.scene, m.direct, 380, w - 380 - numbers_width, h);
  DrawNumbers(m.controller, m.direct, w - numbers_width, numbers_width, h);
  ImGui::Render();
  m.triangles = ImGui::GetDrawData()->TotalIdxCount / 3;
  m.direct_primitives = m.direct.primitive_count();
  const auto layout_end = std::chrono::steady_clock::now();
  glViewport(0, 0, width, height);
  glClearColor(static_cast<float>((kPanelBackground >> IM_COL32_R_SHIFT) & 0xFF) / 255,
               static_cast<float>((kPanelBackground >> IM_COL32_G_SHIFT) & 0xFF) / 255,
               static_cast<float>((kPanelBackground >> IM_COL32_B_SHIFT) & 0xFF) / 255, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  glFinish();  // the rasterisation, apart from the present below
  const auto raster_end = std::chrono::steady_clock::now();
  ++m.frames;
  const bool last = quit || (m.options.max_frames > 0 && m.frames >= m.options.max_frames);
  if (last && !m.options.screenshot_path.empty()) {
    screenshots_due.emplace_back("--screenshot", m.options.screenshot_path);
  }
  for (const auto& [option, path] : screenshots_due) {
    SaveFramebufferPng(m.options.output, option, path, width, height);
    m.screenshots.push_back(path);
  }
  glfwSwapBuffers(m.session.window);
  glFinish();  // the frame is on screen: the time below includes the software renderer's work
  const auto frame_end = std::chrono::steady_clock::now();
  const auto ms = [](auto from, auto to) { return std::chrono::duration<double, std::milli>(to - from).count(); };
  m.frame_ms.push_back(ms(frame_start, frame_end));
  m.phase_ms[static_cast<int>(FramePhase::kUpdate)].push_back(ms(frame_start, update_end));
  m.phase_ms[static_cast<int>(FramePhase::kLayout)].push_back(ms(update_end, layout_end));
  m.phase_ms[static_cast<int>(FramePhase::kRaster)].push_back(ms(layout_end, raster_end));
  m.phase_ms[static_cast<int>(FramePhase::kPresent)].push_back(ms(raster_end, frame_end));
  m.done = last;
  return !last;
}

PanelRunResult PanelWindow::Result() const {
  const Impl& m = *impl_;
  PanelRunResult result;
  result.frames = m.frames;
  result.screenshots = m.screenshots;
  result.elapsed_s = m.SecondsSinceStart();
  result.frame_p50_ms = Percentile(m.frame_ms, 0.50);
  result.frame_p99_ms = Percentile(m.frame_ms, 0.99);
  result.frame_max_ms = m.frame_ms.empty() ? 0 : *std::max_element(m.frame_ms.begin(), m.frame_ms.end());
  for (int i = 0; i < kFramePhases; ++i) result.phase_p50_ms[i] = Percentile(m.phase_ms[i], 0.50);
  result.message = m.controller.message();
  result.last_fault = m.controller.last_fault();
  result.haptic_enabled = m.controller.haptic().enabled();
  result.clutched = m.controller.haptic().clutched();
  result.cap_preset = panel::ToString(m.controller.haptic().cap_preset());
  result.rendering_method = m.controller.haptic().method();
  result.max_hand_force_n = m.max_hand_force_n;
  result.last_frame_triangles = m.triangles;
  result.last_frame_direct_primitives = m.direct_primitives;
  return result;
}

PanelRunResult RunPanelWindow(panel::PanelBackend& backend, const PanelModels& models,
                              const PanelWindowOptions& options) {
  PanelWindow window(backend, models, options);
  while (window.Frame()) {
  }
  return window.Result();
}

}  // namespace robossis::apps
