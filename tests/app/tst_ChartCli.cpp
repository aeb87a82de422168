// sightline-cli chart: a JSON description in, a PNG of the asked size out, with each series drawn
// in its own colour; descriptions it cannot draw get one line naming what is wrong.

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include <QImage>
#include <gtest/gtest.h>

#include "CliRunner.h"

namespace sightline::test {
namespace {

class ChartCli : public CliFolderTest {
protected:
    fs::path spec(const std::string& name, const std::string& text)
    {
        const fs::path file = folder / name;
        std::ofstream(file) << text;
        return file;
    }
};

TEST_F(ChartCli, DrawsEachSeriesInItsOwnColourAtTheAskedSize)
{
    const fs::path file = spec("sweep.json", R"({"title": "time", "x": {"title": "lights", "log": true},
        "y": {"title": "ms", "log": true},
        "series": [{"name": "fast", "points": [[10, 5], [100, 40], [1000, 300]]},
                   {"name": "reference", "points": [[10, 9], [100, 90], [1000, 900]]}]})");
    const fs::path png = folder / "sweep.png";
    const CliRun run = runCli("chart " + file.string() + " --out " + png.string() + " --width 800 --height 500", 120);
    ASSERT_EQ(run.code, 0) << run.err;
    const QImage image(QString::fromStdString(png.string()));
    ASSERT_FALSE(image.isNull());
    EXPECT_EQ(image.size(), QSize(800, 500));
    // The first two of the chart colours (report/SeriesChart.cpp) are there: both lines were drawn.
    std::set<QRgb> colours;
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            colours.insert(image.pixel(x, y) & 0xffffff);
    EXPECT_TRUE(colours.count(qRgb(31, 119, 180) & 0xffffff)) << "the first series' blue";
    EXPECT_TRUE(colours.count(qRgb(214, 39, 40) & 0xffffff)) << "the second series' red";
}

TEST_F(ChartCli, DescriptionsItCannotDrawGetOneLine)
{
    const std::string axes = R"("x": {"title": "n", "log": true}, "y": {"title": "ms"})";
    const fs::path png = folder / "out.png";
    auto refuses = [&](const std::string& name, const std::string& text, const std::string& words) {
        const fs::path file = spec(name, text);
        expectOneLineError(runCli("chart " + file.string() + " --out " + png.string(), 60), words);
    };
    refuses("zero.json", "{" + axes + R"(, "series": [{"name": "a", "points": [[0, 1]]}]})", "logarithmic axis");
    refuses("pair.json", "{" + axes + R"(, "series": [{"name": "a", "points": [[1, 2, 3]]}]})", "point 0");
    refuses("empty.json", "{" + axes + R"(, "series": []})", "no points");
    refuses("noseries.json", "{" + axes + "}", "\"series\"");
    refuses("noaxis.json", R"({"series": []})", "\"x\"");
    refuses("text.json", "not json", "not JSON");
    EXPECT_FALSE(fs::exists(png));
    const fs::path good = spec("good.json", "{" + axes + R"(, "series": [{"name": "a", "points": [[1, 2]]}]})");
    expectOneLineError(runCli("chart " + good.string() + " --out " + good.string(), 60), "would replace");
}

} // namespace
} // namespace sightline::test
