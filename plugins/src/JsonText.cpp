#include "plugins/JsonText.h"

#include <iterator>
#include <new>

#include "base/Error.h"
#include "base/JsonDepth.h"

namespace sightline {

namespace {

using nlohmann::json;

/// nlohmann's messages start "[json.exception.parse_error.101] parse error at line 1, column 2: ...";
/// a user needs the words after the id.
std::string words(const std::string& message)
{
    std::string out = message;
    if (!out.empty() && out.front() == '[')
        if (const auto bracket = out.find("] "); bracket != std::string::npos)
            out.erase(0, bracket + 2);
    if (const auto newline = out.find_first_of("\r\n"); newline != std::string::npos)
        out.erase(newline);
    return out;
}

/// nlohmann's DOM builder, which also keeps where a failure happened: errors that are not
/// parse_error (a number overflowing double, out_of_range.406) carry no byte of their own.
class PositionedDom : public nlohmann::detail::json_sax_dom_parser<json> {
public:
    explicit PositionedDom(json& result) : json_sax_dom_parser(result, false) {}

    template <class Exception>
    bool parse_error(std::size_t position, const std::string&, const Exception& error)
    {
        position_ = position;
        message_ = words(error.what());
        return false; // stop here; parseJsonText reports it
    }

    std::size_t position() const { return position_; }
    const std::string& message() const { return message_; }

private:
    std::size_t position_ = 0;
    std::string message_;
};

/// Frees a DOM leaves first. nlohmann's own destructor first reserves a stack as long as the
/// largest array it holds, and a bad_alloc there, inside a destructor, terminates the program: the
/// usual state right after a huge file ran the parser out of memory. Emptied containers reserve
/// nothing. Recursion is bounded by checkJsonDepth.
void releaseLeavesFirst(json& value)
{
    if (value.is_array()) {
        auto& array = value.get_ref<json::array_t&>();
        while (!array.empty()) {
            releaseLeavesFirst(array.back());
            array.pop_back();
        }
    } else if (value.is_object()) {
        auto& object = value.get_ref<json::object_t&>();
        while (!object.empty()) {
            const auto last = std::prev(object.end());
            releaseLeavesFirst(last->second);
            object.erase(last);
        }
    }
}

} // namespace

json parseJsonText(std::string_view text, const std::string& what)
{
    checkJsonDepth(text, what);
    json result;
    PositionedDom dom(result);
    bool ok = false;
    try {
        ok = json::sax_parse(text, &dom);
    } catch (const json::exception& e) { // anything nlohmann raises outside its parse_error path
        throw Error(what + ": invalid JSON: " + words(e.what()));
    } catch (const std::bad_alloc&) {
        releaseLeavesFirst(result);   // then the caller reports "out of memory" (describeFailure)
        throw;
    }
    if (!ok)
        throw Error(what + ": invalid JSON: " + (dom.message().empty() ? "malformed" : dom.message()) +
                    ", at byte " + std::to_string(dom.position()));
    return result;
}

} // namespace sightline
