// Image textures (see texture.h).
#include "io/texture.h"

#include <cmath>
#include <cstdio>

#include "io/image.h"
#include "io/input_error.h"
#include "io/input_file.h"

namespace lessons {

std::shared_ptr<const ImageTexture> read_texture(const std::string& path, uint64_t max_bytes,
                                                 std::vector<std::string>* notes) {
    check_input_file(path, "texture", max_bytes, "--max-file-mb");
    Image image;
    try {
        image = read_image(path);
    } catch (const std::runtime_error& e) {
        throw InputError(path, 0, "", std::string("cannot read the texture: ") + e.what());
    }
    if (image.width <= 0 || image.height <= 0)
        throw InputError(path, 0, "", "the texture has no pixels");
    if (notes) notes->insert(notes->end(), image.notes.begin(), image.notes.end());
    auto texture = std::make_shared<ImageTexture>();
    texture->width = image.width;
    texture->height = image.height;
    texture->file = path;
    glm::dvec3 sum(0.0);
    for (int j = 0; j < image.height; ++j)
        for (int i = 0; i < image.width; ++i) {
            const Color& c = image.at(i, j);
            const bool finite = std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z);
            if (!finite || min_component(c) < 0.0f || max_component(c) > 1.0f) {
                char msg[240];
                std::snprintf(msg, sizeof msg,
                              "texel (%d, %d) is (%g, %g, %g): a reflectance texture's texels "
                              "must be finite and in [0, 1] (a surface cannot reflect more light "
                              "than it receives)",
                              i, j, c.x, c.y, c.z);
                throw InputError(path, 0, "", msg);
            }
            sum += glm::dvec3(c);
        }
    texture->texels = std::move(image.pixels);
    texture->mean = Color(sum / static_cast<double>(texture->texels.size()));
    return texture;
}

}  // namespace lessons
