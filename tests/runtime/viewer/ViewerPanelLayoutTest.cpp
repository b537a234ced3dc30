// The viewer panel's layout from the font and window sizes, without a window.
#include <gtest/gtest.h>

#include "viewer/ViewerPanel.h"

namespace sluice::rt {
namespace {

// Dear ImGui's default font: 13 pixels tall, 7 pixels per character; the widest slider label,
// "speed range [m/s]", is 17 characters.
constexpr float kFont = 13.0f;
constexpr float kLabel = 17 * 7.0f;

TEST(ViewerPanelLayout, TakesAtMostThirtyPercentOfA960By540Window) {
    const PanelLayout layout = panelLayout(kLabel, kFont, {960.0f, 540.0f});
    EXPECT_LE(layout.width, 0.30f * 960.0f);
    EXPECT_LE(layout.width * layout.maxHeight, 0.30f * 960.0f * 540.0f);
    EXPECT_FLOAT_EQ(layout.maxHeight, 520.0f);
}

TEST(ViewerPanelLayout, LeavesRoomForTheWidestLabelBesideTheSliders) {
    for (const glm::vec2 window :
         {glm::vec2(960, 540), glm::vec2(1280, 720), glm::vec2(640, 480)}) {
        const PanelLayout layout = panelLayout(kLabel, kFont, window);
        EXPECT_GE(layout.itemWidth, 3.0f * kFont) << window.x;
        // Label, slider and padding fit in the panel whenever the slider is not at its minimum.
        if (layout.itemWidth > 3.0f * kFont) {
            EXPECT_LE(kLabel + layout.itemWidth + 3.0f * kFont, layout.width + 0.01f) << window.x;
        }
    }
}

TEST(ViewerPanelLayout, GrowsWithTheFontUntilTheCap) {
    const PanelLayout small = panelLayout(kLabel, kFont, {1920.0f, 1080.0f});
    const PanelLayout large = panelLayout(2.0f * kLabel, 2.0f * kFont, {1920.0f, 1080.0f});
    EXPECT_FLOAT_EQ(large.width, 2.0f * small.width); // uncapped: proportional to the font
    const PanelLayout capped = panelLayout(4.0f * kLabel, 4.0f * kFont, {1920.0f, 1080.0f});
    EXPECT_FLOAT_EQ(capped.width, 0.30f * 1920.0f);
}

} // namespace
} // namespace sluice::rt
