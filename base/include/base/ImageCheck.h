#pragma once
// Checks an image file's bytes before stb_image decodes them. stb trusts a file's header: it
// allocates what the header declares, reads past the end as zeros (a truncated file decodes to
// black, without an error), and its Radiance HDR decoder loops forever on a run-length count of 0.
// Every image Sightline reads (light textures, receiver height images, AO environments, glTF base
// colour textures) goes through these checks first, and is then decoded from the same bytes in memory, so that what
// was checked is what stb sees.
//
// Contract of checkRadianceHdr: returns only when stb_image's HDR decoder will finish on `bytes`,
// writing every pixel from the file's own data:
//   - the header is "#?RADIANCE" or "#?RGBE", lines up to a blank line, with
//     "FORMAT=32-bit_rle_rgbe" among them (the only format stb decodes);
//   - the resolution line is exactly "-Y H +X W" (top-to-bottom rows, left-to-right: the only
//     orientation stb reads), with W and H in [1, kMaxImageSide] and W * H <= kMaxImagePixels;
//   - the pixel data is either flat (4 bytes a pixel, W * H of them) or, where stb expects it
//     (8 <= W < 32768), one new-style run-length scanline per row: the marker 2, 2, W (16 bits),
//     then four channel streams each exactly W long, built of runs (count 129..255, then a value)
//     and dumps (count 1..128, then that many bytes); a count of 0, a run or dump past the end of
//     the scanline, a row whose length is not W, and data that ends early are all refused.
// Everything is checked before a pixel is decoded, so a refusal costs no allocation beyond `bytes`.

#include <string>

namespace sightline::image {

/// Whether `bytes` starts with a Radiance HDR signature (what stb's own test looks for).
bool isRadianceHdr(const std::string& bytes);

/// Throws sightline::Error starting with `name` unless the file is a Radiance HDR that stb decodes
/// completely (contract above). Sets width and height.
void checkRadianceHdr(const std::string& bytes, const std::string& name, int& width, int& height);

/// Throws sightline::Error starting with `name` unless an 8-bit image stb has sized as
/// `width` x `height` is a PNG, JPEG, BMP, TGA or binary PNM (P5, P6) that holds all the data its
/// header declares: every PNG chunk whole up to IEND; every JPEG segment whole up to the end
/// marker; a BMP's, a TGA's or a PNM's pixel bytes in full (a TGA's run-length packets walked to
/// the last pixel). GIF, PSD and PIC, whose data stb cannot be asked to check, are refused.
void checkNotTruncated(const std::string& bytes, const std::string& name, int width, int height);

} // namespace sightline::image
