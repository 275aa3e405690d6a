#include <fmt/format.h>
#include <relief/io/npy.h>

#include <cctype>
#include <cstring>
#include <limits>
#include <optional>
#include <string_view>

namespace relief {

namespace {

constexpr unsigned char kMagic[] = {0x93, 'N', 'U', 'M', 'P', 'Y'};

// The Python literals a .npy header dict is made of: strings, integers, True/False, tuples and
// lists, and the dict itself. Nesting is bounded so that a hostile header cannot exhaust the stack.
struct PyValue {
    enum class Kind { String, Integer, Boolean, Sequence, Dict } kind = Kind::String;
    std::string text;
    int64_t integer = 0;
    bool boolean = false;
    std::vector<PyValue> items;     // a tuple's or a list's items, a dict's values
    std::vector<std::string> keys;  // a dict's keys (strings only), one per item
};

class PyLiteralParser {
  public:
    explicit PyLiteralParser(std::string_view text) : m_text(text) {}

    std::optional<PyValue> parseAll() {
        auto value = parse(0);
        skipSpace();
        if (!value || m_pos != m_text.size()) return std::nullopt;
        return value;
    }

  private:
    static constexpr int kMaxDepth = 8;

    void skipSpace() {
        while (m_pos < m_text.size() && std::isspace(static_cast<unsigned char>(m_text[m_pos])))
            ++m_pos;
    }
    bool eat(char c) {
        skipSpace();
        if (m_pos < m_text.size() && m_text[m_pos] == c) {
            ++m_pos;
            return true;
        }
        return false;
    }
    bool eatWord(std::string_view word) {
        skipSpace();
        if (m_text.substr(m_pos, word.size()) != word) return false;
        m_pos += word.size();
        return true;
    }

    std::optional<PyValue> parse(int depth) {
        if (depth > kMaxDepth) return std::nullopt;
        skipSpace();
        if (m_pos >= m_text.size()) return std::nullopt;
        PyValue v;
        const char c = m_text[m_pos];
        if (c == '\'' || c == '"') {
            // Escapes are refused: NumPy's own dtypes and field names written here need none.
            const size_t end = m_text.find(c, m_pos + 1);
            if (end == std::string_view::npos) return std::nullopt;
            v.text = std::string(m_text.substr(m_pos + 1, end - m_pos - 1));
            if (v.text.find('\\') != std::string::npos) return std::nullopt;
            m_pos = end + 1;
            return v;
        }
        if (std::isdigit(static_cast<unsigned char>(c))) {
            v.kind = PyValue::Kind::Integer;
            for (; m_pos < m_text.size() && std::isdigit(static_cast<unsigned char>(m_text[m_pos]));
                 ++m_pos) {
                const int digit = m_text[m_pos] - '0';
                if (v.integer > (std::numeric_limits<int64_t>::max() - digit) / 10)
                    return std::nullopt;
                v.integer = v.integer * 10 + digit;
            }
            return v;
        }
        for (const bool word : {true, false})
            if (eatWord(word ? "True" : "False")) {
                v.kind = PyValue::Kind::Boolean;
                v.boolean = word;
                return v;
            }
        if (c == '(' || c == '[' || c == '{') {
            const char close = c == '(' ? ')' : c == '[' ? ']' : '}';
            v.kind = c == '{' ? PyValue::Kind::Dict : PyValue::Kind::Sequence;
            ++m_pos;
            while (!eat(close)) {
                auto item = parse(depth + 1);
                if (!item) return std::nullopt;
                if (v.kind == PyValue::Kind::Dict) {
                    if (item->kind != PyValue::Kind::String || !eat(':')) return std::nullopt;
                    auto value = parse(depth + 1);
                    if (!value) return std::nullopt;
                    v.keys.push_back(item->text);
                    v.items.push_back(std::move(*value));
                } else {
                    v.items.push_back(std::move(*item));
                }
                if (!eat(',')) {
                    if (!eat(close)) return std::nullopt;
                    break;
                }
            }
            return v;
        }
        return std::nullopt;
    }

    std::string_view m_text;
    size_t m_pos = 0;
};

// Bytes of one value of a NumPy type string, or 0 for a type relief does not read.
int64_t typeBytes(std::string_view type) {
    static constexpr std::pair<std::string_view, int> kTypes[] = {
        {"|b1", 1}, {"|u1", 1}, {"|i1", 1}, {"<u2", 2}, {"<i2", 2}, {"<f2", 2},
        {"<u4", 4}, {"<i4", 4}, {"<f4", 4}, {"<u8", 8}, {"<i8", 8}, {"<f8", 8}};
    for (const auto& [name, bytes] : kTypes)
        if (name == type) return bytes;
    return 0;
}

Result<NpyField> fieldOf(std::string name, std::string type, const std::string& what) {
    // '=' is the native order, little endian on every machine relief runs on.
    if (!type.empty() && type[0] == '=') type[0] = '<';
    if (type.size() == 3 && type[0] == '<' &&
        (type[1] == 'b' || type[1] == 'u' || type[1] == 'i') && type[2] == '1')
        type[0] = '|';
    if (!type.empty() && type[0] == '>')
        return makeError(ErrorKind::Unsupported,
                         "{}: big-endian dtype '{}' (relief reads little-endian .npy)", what, type);
    if (typeBytes(type) == 0)
        return makeError(ErrorKind::Unsupported, "{}: dtype '{}' is not one relief reads", what,
                         type);
    return NpyField{std::move(name), std::move(type)};
}

Error badHeader(const std::string& what, std::string_view problem) {
    return makeError(ErrorKind::InvalidInput, "{}: bad .npy header: {}", what, problem);
}

Result<NpyHeader> headerOf(const PyValue& dict, const std::string& what) {
    NpyHeader h;
    const PyValue *descr = nullptr, *fortran = nullptr, *shape = nullptr;
    for (size_t k = 0; k < dict.keys.size(); ++k) {
        const std::string& key = dict.keys[k];
        const PyValue** slot = key == "descr"           ? &descr
                               : key == "fortran_order" ? &fortran
                               : key == "shape"         ? &shape
                                                        : nullptr;
        if (!slot || *slot)
            return badHeader(what, fmt::format("unexpected or repeated key '{}'", key));
        *slot = &dict.items[k];
    }
    if (!descr || !fortran || !shape)
        return badHeader(what, "it needs the keys 'descr', 'fortran_order' and 'shape'");
    if (fortran->kind != PyValue::Kind::Boolean)
        return badHeader(what, "fortran_order is not True/False");
    if (fortran->boolean)
        return makeError(
            ErrorKind::Unsupported,
            "{}: fortran_order=True (relief reads C-order arrays: np.ascontiguousarray)", what);
    if (descr->kind == PyValue::Kind::String) {
        auto field = fieldOf("", descr->text, what);
        if (!field) return field.error();
        h.fields.push_back(std::move(*field));
    } else if (descr->kind == PyValue::Kind::Sequence && !descr->items.empty()) {
        for (const PyValue& f : descr->items) {
            if (f.kind != PyValue::Kind::Sequence || f.items.size() != 2 ||
                f.items[0].kind != PyValue::Kind::String ||
                f.items[1].kind != PyValue::Kind::String)
                return makeError(ErrorKind::Unsupported,
                                 "{}: structured dtype fields must be ('name', 'type') pairs",
                                 what);
            auto field = fieldOf(f.items[0].text, f.items[1].text, what);
            if (!field) return field.error();
            h.fields.push_back(std::move(*field));
        }
    } else {
        return badHeader(what, "descr is neither a type string nor a list of fields");
    }
    for (const NpyField& f : h.fields) h.itemBytes += typeBytes(f.type);
    if (shape->kind != PyValue::Kind::Sequence) return badHeader(what, "shape is not a tuple");
    h.elements = 1;
    for (const PyValue& d : shape->items) {
        if (d.kind != PyValue::Kind::Integer) return badHeader(what, "shape holds a non-integer");
        h.shape.push_back(d.integer);
        // At most 2^56 bytes of data, so that no size computed from the shape overflows.
        if (d.integer != 0 && h.elements > (int64_t(1) << 56) / h.itemBytes / d.integer)
            return makeError(ErrorKind::InvalidInput, "{}: absurd shape {}", what,
                             npyShapeText(h.shape));
        h.elements *= d.integer;
    }
    return h;
}

std::string descrText(std::span<const NpyField> fields) {
    if (fields.size() == 1 && fields[0].name.empty()) return fmt::format("'{}'", fields[0].type);
    std::string text = "[";
    for (const NpyField& f : fields)
        text += fmt::format("{}('{}', '{}')", text.size() > 1 ? ", " : "", f.name, f.type);
    return text + "]";
}

}  // namespace

std::string npyShapeText(std::span<const int64_t> shape) {
    std::string text = "(";
    for (size_t k = 0; k < shape.size(); ++k) text += fmt::format("{}{}", k ? ", " : "", shape[k]);
    return text + (shape.size() == 1 ? ",)" : ")");
}

std::string npyPreamble(std::span<const NpyField> fields, std::span<const int64_t> shape) {
    std::string dict = fmt::format("{{'descr': {}, 'fortran_order': False, 'shape': {}, }}",
                                   descrText(fields), npyShapeText(shape));
    // Magic (6), version (2), header length (2), dict, spaces and '\n' to a multiple of 64.
    const size_t unpadded = 10 + dict.size() + 1;
    dict.append((64 - unpadded % 64) % 64, ' ');
    dict.push_back('\n');
    std::string out(reinterpret_cast<const char*>(kMagic), sizeof kMagic);
    out += '\x01';
    out += '\x00';
    out += char(dict.size() & 0xff);
    out += char(dict.size() >> 8);
    return out + dict;
}

Result<NpyHeader> readNpyHeader(std::FILE* in, int64_t fileSize, const std::string& what) {
    unsigned char fixed[12] = {};
    const size_t got = std::fread(fixed, 1, 8, in);
    if (got < 8 || std::memcmp(fixed, kMagic, sizeof kMagic) != 0)
        return makeError(ErrorKind::InvalidInput, "{}: not a .npy file (no \\x93NUMPY magic)",
                         what);
    const int major = fixed[6], minor = fixed[7];
    if ((major != 1 && major != 2) || minor != 0)
        return makeError(ErrorKind::Unsupported,
                         "{}: .npy format version {}.{} (relief reads 1.0 and 2.0)", what, major,
                         minor);
    const size_t lengthBytes = major == 1 ? 2 : 4;
    if (std::fread(fixed + 8, 1, lengthBytes, in) != lengthBytes)
        return badHeader(what, "truncated before its length");
    int64_t length = 0;
    for (size_t k = lengthBytes; k-- > 0;) length = length * 256 + fixed[8 + k];
    if (length > kMaxNpyHeaderBytes)
        return badHeader(what,
                         fmt::format("{} bytes long (at most {})", length, kMaxNpyHeaderBytes));
    std::string text(size_t(length), '\0');
    if (std::fread(text.data(), 1, text.size(), in) != text.size())
        return badHeader(what, "truncated");
    if (text.empty() || text.back() != '\n')
        return badHeader(what, "it does not end with a newline");
    auto dict = PyLiteralParser(text).parseAll();
    if (!dict || dict->kind != PyValue::Kind::Dict)
        return badHeader(
            what, "not a Python dict literal {'descr': ..., 'fortran_order': ..., 'shape': ...}");
    auto header = headerOf(*dict, what);
    if (!header) return header.error();
    header->dataOffset = int64_t(8 + lengthBytes) + length;
    const int64_t needed = header->elements * header->itemBytes;
    const int64_t present = fileSize - header->dataOffset;
    if (present < needed)
        return makeError(ErrorKind::InvalidInput,
                         "{}: truncated .npy: shape {} needs {} bytes of data, the file has {}",
                         what, npyShapeText(header->shape), needed, present);
    if (present > needed)
        return makeError(ErrorKind::InvalidInput,
                         "{}: {} bytes after the data of shape {} (a wrong shape?)", what,
                         present - needed, npyShapeText(header->shape));
    return header;
}

}  // namespace relief
