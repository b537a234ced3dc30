// closestMatch and didYouMean: the suggestions error messages make for mistyped words.
#include <gtest/gtest.h>

#include "sluice/format/support/Suggest.h"

using namespace sluice::format;

TEST(Suggest, EditDistanceCountsInsertionsDeletionsAndSubstitutions) {
    EXPECT_EQ(editDistance("", ""), 0u);
    EXPECT_EQ(editDistance("bake", "bake"), 0u);
    EXPECT_EQ(editDistance("bkae", "bake"), 2u); // a swap is two substitutions
    EXPECT_EQ(editDistance("resolutoin", "resolution"), 2u);
    EXPECT_EQ(editDistance("kitten", "sitting"), 3u);
    EXPECT_EQ(editDistance("", "abc"), 3u);
}

TEST(Suggest, SuggestsTheNearestCandidateWithinTwoEdits) {
    const std::vector<std::string> commands{"bake", "batch", "validate", "info", "export"};
    EXPECT_EQ(closestMatch("bkae", commands).value_or(""), "bake");
    EXPECT_EQ(closestMatch("valdiate", commands).value_or(""), "validate");
    EXPECT_EQ(closestMatch("exprot", commands).value_or(""), "export");
    EXPECT_FALSE(closestMatch("frob", commands));
    EXPECT_FALSE(closestMatch("", commands));
    EXPECT_EQ(didYouMean("bkae", commands), " (did you mean 'bake'?)");
    EXPECT_EQ(didYouMean("frob", commands), "");
}

TEST(Suggest, ShortWordsNeedACloserMatch) {
    // One edit in a two-letter word is another word, not a typo.
    const std::vector<std::string> flags{"-o", "-j"};
    EXPECT_FALSE(closestMatch("-x", flags));
    EXPECT_EQ(closestMatch("--resolutoin", {"--resolution", "--padding"}).value_or(""),
              "--resolution");
    EXPECT_FALSE(closestMatch(std::string(65, 'a'), {std::string(65, 'a')}));
}

TEST(Suggest, CountedNounsAreSingularForOneOnly) {
    EXPECT_EQ(plural(0, "collider"), "0 colliders");
    EXPECT_EQ(plural(1, "collider"), "1 collider");
    EXPECT_EQ(plural(2, "vertex", "vertices"), "2 vertices");
}
