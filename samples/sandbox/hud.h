#pragma once
// The sandbox's on-screen display, drawn through Engine::set_overlay: a crosshair (four arms
// around a free centre pixel, so screenshots show the world under it), the hotbar with the block
// colours and the selected slot framed, and a text panel (mode, save state, messages, F3 stats,
// F1 help, the Esc menu). Text is set in Dear ImGui's built-in font (ProggyClean, from its
// ImFontAtlas) onto the CPU atlas; only changed text re-uploads the atlas. Main thread.
#include <memory>
#include <string>
#include <vector>

#include <vx/vx.h>

#include "hotbar.h"

struct ImFontAtlas;

namespace sandbox {

class Hud {
public:
    // `blocks`: the engine's palette (id i + 1 = blocks[i]), for the hotbar colours.
    explicit Hud(std::vector<vx::BlockType> blocks);
    ~Hud();
    Hud(const Hud&) = delete;
    Hud& operator=(const Hud&) = delete;

    // The overlay for a framebuffer of width × height pixels showing `lines` of text top left.
    const vx::Overlay& build(uint32_t width, uint32_t height, const Hotbar& hotbar, const std::vector<std::string>& lines);

private:
    void draw_text(const std::vector<std::string>& lines);
    glm::u8vec4 block_colour(vx::BlockId id) const;

    std::vector<vx::BlockType> m_blocks;
    std::unique_ptr<ImFontAtlas> m_font;
    const unsigned char* m_glyphs = nullptr; // Alpha8 font atlas.
    int m_glyphs_w = 0, m_glyphs_h = 0;
    vx::Overlay m_overlay;
    std::vector<std::string> m_text;     // Drawn into the atlas now.
    std::vector<vx::BlockId> m_palette;  // Hotbar ids drawn into the atlas now.
    int m_text_w = 0, m_text_h = 0;      // Text panel size in atlas pixels.
};

} // namespace sandbox
