#include "ui.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include <imgui.h>

namespace sandbox {
namespace {

constexpr ImU32 kCrosshair = IM_COL32(255, 255, 255, 255);
constexpr ImU32 kSlotFrame = IM_COL32(40, 40, 40, 200);
constexpr ImU32 kSelected = IM_COL32(255, 255, 255, 255);
constexpr ImGuiWindowFlags kPanel = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                    ImGuiWindowFlags_NoInputs | ImGuiWindowFlags_NoSavedSettings |
                                    ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav;

uint8_t srgb_encode(float linear) {
    const float c = std::clamp(linear, 0.f, 1.f);
    const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.f / 2.4f) - 0.055f;
    return uint8_t(std::lround(s * 255.f));
}

// A filled rectangle of whole pixels [x0, x1) x [y0, y1) (no anti-aliased fringe).
void pixels(ImDrawList* dl, int x0, int y0, int x1, int y1, ImU32 c) {
    dl->AddRectFilled(ImVec2(float(x0), float(y0)), ImVec2(float(x1), float(y1)), c);
}

} // namespace

Ui::Ui(std::vector<vx::BlockType> blocks) : m_blocks(std::move(blocks)) {
    m_ctx = ImGui::CreateContext();
    ImGui::SetCurrentContext(m_ctx);
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr; // No imgui.ini next to the player's world.
    io.Fonts->AddFontDefault();
    unsigned char* rgba = nullptr;
    io.Fonts->GetTexDataAsRGBA32(&rgba, &m_tex_w, &m_tex_h);
    m_texture.assign(rgba, rgba + size_t(m_tex_w) * size_t(m_tex_h) * 4);
    io.Fonts->SetTexID(ImTextureID(1)); // The one texture (the engine's UI texture).
    ImGui::StyleColorsDark();
    ImGui::GetStyle().WindowRounding = 3.f;
}

Ui::~Ui() { ImGui::DestroyContext(m_ctx); }

vx::Status Ui::attach(vx::Engine& engine) const {
    return engine.set_ui_texture(uint32_t(m_tex_w), uint32_t(m_tex_h), m_texture);
}

bool Ui::wants_mouse() const { return ImGui::GetIO().WantCaptureMouse; }

uint32_t Ui::block_colour(vx::BlockId id) const {
    if (id == vx::kAir || id > m_blocks.size())
        return IM_COL32(128, 128, 128, 255);
    const vx::BlockType& b = m_blocks[id - 1u];
    const glm::vec3 c = glm::max(b.albedo, glm::min(b.emission, glm::vec3(1.f)));
    return IM_COL32(srgb_encode(c.r), srgb_encode(c.g), srgb_encode(c.b), 255);
}

void Ui::draw_crosshair_and_hotbar(const UiInput& in, const Hotbar& hotbar, bool menu) {
    const int W = int(in.width), H = int(in.height);
    const int scale = std::max(1, std::min(W, H) / 400); // Bigger on big windows.
    // Crosshair (not over the menu): four arms with a one-pixel gap around the centre pixel
    // (W/2, H/2), left free.
    if (!menu) {
        ImDrawList* fg = ImGui::GetForegroundDrawList();
        const int cx = W / 2, cy = H / 2, arm = 4 * scale, t = scale;
        pixels(fg, cx - arm - 1, cy, cx - 1, cy + t, kCrosshair);
        pixels(fg, cx + 2, cy, cx + 2 + arm, cy + t, kCrosshair);
        pixels(fg, cx, cy - arm - 1, cx + t, cy - 1, kCrosshair);
        pixels(fg, cx, cy + 2, cx + t, cy + 2 + arm, kCrosshair);
    }
    // Hotbar: bottom centre, the block colours, the selected slot framed in white.
    ImDrawList* bg = ImGui::GetBackgroundDrawList();
    const int slot = std::max(6, std::min(20 * scale, (W - 20) / Hotbar::kSlots)), gap = std::max(1, slot / 8);
    const int bar_w = Hotbar::kSlots * slot, x0 = (W - bar_w) / 2, y0 = H - slot - 2 * gap;
    m_hotbar_top = y0 - gap;
    pixels(bg, x0 - gap, y0 - gap, x0 + bar_w + gap, y0 + slot + gap, kSlotFrame);
    for (int i = 0; i < Hotbar::kSlots; ++i) {
        const int x = x0 + i * slot;
        if (i == hotbar.selected_slot())
            pixels(bg, x, y0 - gap, x + slot, y0 + slot + gap, kSelected);
        pixels(bg, x + gap, y0 + gap, x + slot - gap, y0 + slot - gap, block_colour(hotbar.slot(i)));
    }
}

UiActions Ui::draw_windows(const UiInput& in, const UiView& v) {
    UiActions act;
    ImGui::SetNextWindowPos(ImVec2(4, 4));
    ImGui::SetNextWindowBgAlpha(0.55f);
    if (ImGui::Begin("status", nullptr, kPanel)) {
        ImGui::TextUnformatted(v.status.c_str());
        for (const std::string& l : v.stats) // F3, under the status line.
            ImGui::TextUnformatted(l.c_str());
    }
    ImGui::End();
    if (!v.help.empty()) { // F1: bottom left, above the hotbar (the stats are top left).
        ImGui::SetNextWindowPos(ImVec2(4, float(m_hotbar_top - 4)), ImGuiCond_Always, ImVec2(0, 1));
        ImGui::SetNextWindowBgAlpha(0.7f);
        if (ImGui::Begin("Help (F1)", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoInputs |
                                                   ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing))
            for (const std::string& l : v.help)
                ImGui::TextUnformatted(l.c_str());
        ImGui::End();
    }
    if (v.menu) {
        ImGui::SetNextWindowPos(ImVec2(float(in.width) * 0.5f, float(in.height) * 0.5f), ImGuiCond_Always,
                                ImVec2(0.5f, 0.5f));
        if (ImGui::Begin("Paused", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                                                ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoMove)) {
            if (ImGui::Button("Resume", ImVec2(160, 0)))
                act.resume = true;
            ImGui::Separator();
            bool on[4] = {v.shadows, v.reflections, v.denoise, v.raster};
            static const char* const kLabel[4] = {"Shadows (G)", "Reflections (R)", "Denoiser (N)", "Raster pipeline (P)"};
            static const char* const kToggle[4] = {"shadows", "reflections", "denoise", "raster"};
            for (int i = 0; i < 4; ++i)
                if (ImGui::Checkbox(kLabel[i], &on[i]))
                    act.toggles.push_back(kToggle[i]);
            ImGui::Separator();
            if (ImGui::Button("Quit", ImVec2(160, 0)))
                act.quit = true;
        }
        ImGui::End();
    }
    return act;
}

// ImDrawData (16-bit indices per list) into one list of 32-bit indices for Engine::set_ui.
void Ui::convert() {
    const ImDrawData* d = ImGui::GetDrawData();
    m_list.vertices.clear();
    m_list.indices.clear();
    m_list.cmds.clear();
    if (!d)
        return;
    for (int n = 0; n < d->CmdListsCount; ++n) {
        const ImDrawList* l = d->CmdLists[n];
        const uint32_t vbase = uint32_t(m_list.vertices.size()), ibase = uint32_t(m_list.indices.size());
        for (const ImDrawVert& v : l->VtxBuffer)
            m_list.vertices.push_back({{v.pos.x, v.pos.y}, {v.uv.x, v.uv.y}, v.col});
        for (ImDrawIdx i : l->IdxBuffer)
            m_list.indices.push_back(vbase + i);
        for (const ImDrawCmd& c : l->CmdBuffer) {
            if (c.UserCallback || c.ElemCount == 0)
                continue; // No callbacks in this UI.
            const ImVec4 r = c.ClipRect; // DisplayPos is (0, 0) and the scale 1: pixels already.
            const glm::ivec4 clip{int(std::floor(r.x)), int(std::floor(r.y)), int(std::ceil(r.z)), int(std::ceil(r.w))};
            // VtxOffset stays 0: RendererHasVtxOffset is not set, so each list fits 16-bit indices.
            m_list.cmds.push_back({ibase + c.IdxOffset, c.ElemCount, clip});
        }
    }
}

UiActions Ui::frame(const UiInput& in, const Hotbar& hotbar, const UiView& view) {
    ImGui::SetCurrentContext(m_ctx);
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(float(std::max(in.width, 1u)), float(std::max(in.height, 1u)));
    io.DeltaTime = float(std::max(in.dt, 1e-4));
    io.MousePos = in.mouse_free ? ImVec2(in.mouse.x, in.mouse.y) : ImVec2(-FLT_MAX, -FLT_MAX);
    for (int b = 0; b < 3; ++b)
        io.MouseDown[b] = in.mouse_free && in.mouse_down[size_t(b)];
    ImGui::NewFrame();
    draw_crosshair_and_hotbar(in, hotbar, view.menu);
    const UiActions act = draw_windows(in, view);
    ImGui::Render();
    convert();
    return act;
}

} // namespace sandbox
