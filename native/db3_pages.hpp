// A rosbag2 .db3's ``messages`` table read from its b-tree pages, in the order sqlite's ``NOT INDEXED`` scan
// gives its rows (the table's rowid order), without sqlite: sqlite spends ~1,500 instructions a row where a
// leaf cell is a few varints and a blob. It reads only what it can prove it reads as sqlite does and throws
// ``PageError`` at anything else (a page of an unexpected kind, a cell or record out of its bounds, a page
// number out of the file, a page met twice, a tree deeper than sqlite's cursors go, an overflow chain cut
// short); its caller then reads the table through sqlite, which gives the same rows or says what is wrong.
//
// From https://www.sqlite.org/fileformat2.html (integers big-endian): the 100-byte file header gives the
// page size (u16 at 16, 1 meaning 65536), the bytes reserved at each page's end (u8 at 20) and the pages
// in the file (u32 at 28, when the u32 at 24 equals the one at 92). A table b-tree page starts with its
// kind (0x05 interior, 0x0D leaf), the u16 count of its cells at 3 and where their content starts at 5
// (0 meaning 65536); an interior page's right-most child is the u32 at 8. Its cells' u16 offsets follow
// its header (12 bytes interior, 8 leaf). An interior cell is its left child's u32 and a key; a leaf cell
// a varint payload size, a varint rowid, the payload's first bytes (all of it when it fits) and, when it
// spills, the u32 number of its first overflow page; an overflow page holds the next one's number, then
// bytes. A record is a varint header size (counting itself), a varint serial type per column, the values.
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace db3 {

struct PageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Columns of the rows read: each row's integers, where its blob starts in ``data`` and its length.
struct Fetched {
    std::vector<int64_t> topic, time, id, start, length;
    std::vector<uint8_t>* data;
};

// Which topic ids a reader takes (``wanted``: every one where empty) and of which it takes a header's
// bytes only (``headed``: the first ``header_bytes`` of a blob not compressed), as db3.py's query asks.
struct Topics {
    std::vector<uint8_t> wanted, headed;
    size_t header_bytes = 0;
};

class TablePages {
   public:
    // The table whose root page is ``root`` in the file at ``path``.
    TablePages(const std::string& path, uint32_t root, Topics topics) : topics_(std::move(topics)) {
        fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
        if (fd_ < 0) throw PageError("cannot open the file");
        try {
            read_header();
            enter(root, true);
        } catch (...) {
            ::close(fd_);
            throw;
        }
    }
    ~TablePages() { ::close(fd_); }
    TablePages(const TablePages&) = delete;
    TablePages& operator=(const TablePages&) = delete;

    // Rows into ``got`` until ``rows`` of them or ``bytes`` of blobs are there, or the table ends;
    // false at its end.
    bool step(Fetched& got, int64_t rows, int64_t bytes) {
        while (static_cast<int64_t>(got.topic.size()) < rows && static_cast<int64_t>(got.data->size()) < bytes) {
            if (leaf_ != 0 && cell_ < cells_) {
                const uint8_t* page = this->page(leaf_);
                const uint32_t end = first_cell(page, kLeafHeader);
                // Cells of one page while the fetch has room: the page stays where ``page`` points (an
                // overflow page is read elsewhere).
                while (cell_ < cells_ && static_cast<int64_t>(got.topic.size()) < rows &&
                       static_cast<int64_t>(got.data->size()) < bytes) {
                    leaf_cell(page, u16(page + kLeafHeader + 2 * cell_++), end, got);
                }
                continue;
            }
            leaf_ = 0;
            if (!next_leaf()) return false;
        }
        return true;
    }

   private:
    static constexpr uint32_t kLeafHeader = 8, kInteriorHeader = 12;
    static constexpr uint8_t kInterior = 0x05, kLeaf = 0x0D;
    static constexpr size_t kMaxDepth = 20;  // sqlite's cursors go no deeper (BTCURSOR_MAX_DEPTH)
    static constexpr size_t kChunkBytes = 256 * 1024;
    static constexpr uint8_t kZstd[4] = {0x28, 0xB5, 0x2F, 0xFD};

    struct Level {
        std::vector<uint8_t> page;  // an interior page, held while its children are read
        uint32_t cells = 0, next = 0;  // its cells, and the next child to read (``cells``: the right-most)
    };

    static uint32_t u16(const uint8_t* p) { return (uint32_t{p[0]} << 8) | p[1]; }
    static uint32_t u32(const uint8_t* p) {
        return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | p[3];
    }

    // A varint at ``pos`` no further than ``end``; ``pos`` moved past it.
    static uint64_t varint(const uint8_t* p, uint32_t& pos, uint32_t end) {
        uint64_t value = 0;
        for (int i = 0; i < 8; ++i) {
            if (pos >= end) throw PageError("a varint runs past its cell");
            const uint8_t byte = p[pos++];
            value = (value << 7) | (byte & 0x7F);
            if (!(byte & 0x80)) return value;
        }
        if (pos >= end) throw PageError("a varint runs past its cell");
        return (value << 8) | p[pos++];
    }

    void read_header() {
        uint8_t header[100];
        read_at(header, sizeof header, 0);
        if (std::memcmp(header, "SQLite format 3\0", 16) != 0) throw PageError("not an SQLite database");
        const uint32_t size = u16(header + 16);
        page_size_ = size == 1 ? 65536 : size;
        if (page_size_ < 512 || page_size_ > 65536 || (page_size_ & (page_size_ - 1))) {
            throw PageError("a page size sqlite does not write");
        }
        usable_ = page_size_ - header[20];
        if (usable_ < 480 || header[18] < 1 || header[18] > 2 || header[19] < 1 || header[19] > 2 ||
            header[21] != 64 || header[22] != 32 || header[23] != 32) {
            throw PageError("a file header this reader does not read");
        }
        struct stat st {};
        if (::fstat(fd_, &st) != 0 || st.st_size <= 0 || st.st_size % page_size_ != 0 ||
            st.st_size / page_size_ > UINT32_MAX - 1) {
            throw PageError("a file that is not whole pages");
        }
        pages_ = static_cast<uint32_t>(st.st_size / page_size_);
        const uint32_t said = u32(header + 28);
        if (said != 0 && u32(header + 24) == u32(header + 92) && said != pages_) {
            throw PageError("the file holds another number of pages than its header says");
        }
        lock_page_ = static_cast<uint32_t>((uint64_t{1} << 30) / page_size_) + 1;
        visited_.assign(pages_ / 8 + 1, 0);
        chunk_.resize(std::max<size_t>(kChunkBytes, page_size_));
        overflow_.resize(page_size_);
    }

    void read_at(uint8_t* into, size_t count, uint64_t offset) const {
        while (count) {
            const ssize_t got = ::pread(fd_, into, count, static_cast<off_t>(offset));
            if (got < 0 && errno == EINTR) continue;
            if (got <= 0) throw PageError("the file is shorter than its pages");
            into += got;
            offset += static_cast<uint64_t>(got);
            count -= static_cast<size_t>(got);
        }
    }

    void check_number(uint32_t number) const {
        if (number < 2 || number > pages_ || number == lock_page_) throw PageError("a page number out of the file");
    }

    // Page ``number``, read with the pages after it (a table's leaves mostly follow each other); valid
    // until the next call.
    const uint8_t* page(uint32_t number) {
        if (number < chunk_first_ || number >= chunk_first_ + chunk_pages_) {
            const uint32_t fit = static_cast<uint32_t>(chunk_.size() / page_size_);
            chunk_pages_ = std::min(fit, pages_ - number + 1);
            chunk_first_ = number;
            read_at(chunk_.data(), size_t{chunk_pages_} * page_size_, uint64_t{number - 1} * page_size_);
        }
        return chunk_.data() + size_t{number - chunk_first_} * page_size_;
    }

    // Where a page's cell content starts, checked against its cells' offsets; every cell offset must lie
    // between it and the usable end.
    uint32_t first_cell(const uint8_t* page, uint32_t header) const {
        const uint32_t content = u16(page + 5) == 0 ? 65536 : u16(page + 5);
        const uint32_t cells = u16(page + 3);
        if (cells > (usable_ - 8) / 6 || header + 2 * cells > content || content > usable_) {
            throw PageError("a page whose cells do not fit it");
        }
        return content;
    }

    // Page ``number`` of the tree: an interior page held on the stack, or the leaf whose cells come next.
    void enter(uint32_t number, bool root = false) {
        check_number(number);
        if (visited_[number >> 3] & (1u << (number & 7))) throw PageError("a page met twice in the tree");
        visited_[number >> 3] |= static_cast<uint8_t>(1u << (number & 7));
        if (levels_.size() >= kMaxDepth) throw PageError("a tree deeper than sqlite reads");
        const uint8_t* page = this->page(number);
        const uint32_t cells = u16(page + 3);
        // sqlite refuses a page without cells but a root leaf (an empty table).
        if (page[0] == kInterior && cells > 0) {
            const uint32_t content = first_cell(page, kInteriorHeader);
            for (uint32_t i = 0; i < cells; ++i) {
                const uint32_t at = u16(page + kInteriorHeader + 2 * i);
                if (at < content || at + 4 > usable_) throw PageError("an interior cell out of its page");
            }
            levels_.push_back(Level{std::vector<uint8_t>(page, page + page_size_), cells, 0});
        } else if (page[0] == kLeaf && (cells > 0 || root)) {
            first_cell(page, kLeafHeader);
            leaf_ = number;
            cells_ = cells;
            cell_ = 0;
        } else {
            throw PageError("a page that is not a table page");
        }
    }

    // Down to the next leaf; false when the tree is read.
    bool next_leaf() {
        while (!levels_.empty()) {
            Level& level = levels_.back();
            if (level.next > level.cells) {
                levels_.pop_back();
                continue;
            }
            const uint8_t* page = level.page.data();
            const uint32_t child = level.next < level.cells ? u32(page + u16(page + kInteriorHeader + 2 * level.next))
                                                            : u32(page + 8);
            ++level.next;
            enter(child);
            if (leaf_ != 0) return true;
        }
        return false;
    }

    // A column's serial type's bytes; the reserved types 10 and 11 are not read.
    static uint64_t column_bytes(uint64_t type) {
        static constexpr uint8_t kFixed[12] = {0, 1, 2, 3, 4, 6, 8, 8, 0, 0, 0, 0};
        if (type == 10 || type == 11) throw PageError("a reserved serial type");
        return type < 12 ? kFixed[type] : (type - 12) / 2;
    }

    static bool integer(uint64_t type) { return (type >= 1 && type <= 6) || type == 8 || type == 9; }

    static int64_t integer_at(const uint8_t* p, uint64_t type) {
        if (type == 8 || type == 9) return static_cast<int64_t>(type - 8);
        const uint64_t bytes = column_bytes(type);
        uint64_t value = p[0] & 0x80 ? ~uint64_t{0} : 0;  // sign-extended
        for (uint64_t i = 0; i < bytes; ++i) value = (value << 8) | p[i];
        return static_cast<int64_t>(value);
    }

    // One leaf cell at ``at``: its row into ``got`` when it is a wanted message.
    void leaf_cell(const uint8_t* page, uint32_t at, uint32_t content, Fetched& got) {
        if (at < content || at >= usable_) throw PageError("a leaf cell out of its page");
        uint32_t pos = at;
        const uint64_t payload = varint(page, pos, usable_);
        const int64_t rowid = static_cast<int64_t>(varint(page, pos, usable_));
        if (payload > uint64_t{pages_} * usable_) throw PageError("a cell larger than the file");
        // The payload's bytes on this page (the format's X, M and K).
        const uint64_t most = usable_ - 35;
        uint64_t local = payload;
        if (payload > most) {
            const uint64_t least = (uint64_t{usable_ - 12} * 32 / 255) - 23;
            const uint64_t k = least + (payload - least) % (usable_ - 4);
            local = k <= most ? k : least;
        }
        if (pos + local + (local < payload ? 4 : 0) > usable_) throw PageError("a cell runs past its page");
        const uint8_t* record = page + pos;
        // The record's header, on this page.
        uint32_t at_type = 0;
        const uint64_t header = varint(record, at_type, static_cast<uint32_t>(local));
        if (header > local) throw PageError("a record header that spills");
        uint64_t types[4];
        uint64_t size = header;
        for (uint64_t& type : types) {
            type = varint(record, at_type, static_cast<uint32_t>(header));
            size += column_bytes(type);
        }
        // Exactly the table's four columns, the first the rowid's stand-in (id INTEGER PRIMARY KEY).
        if (at_type != header || size != payload || types[0] != 0) throw PageError("a record not of the table's shape");
        const uint64_t blob_at = header + column_bytes(types[1]) + column_bytes(types[2]);
        if (blob_at > local) throw PageError("a record's integers spill");
        const uint64_t blob = column_bytes(types[3]);
        const int64_t topic = integer(types[1]) ? integer_at(record + header, types[1]) : 0;
        const std::vector<uint8_t>& wanted = topics_.wanted;
        const bool message = integer(types[1]) && integer(types[2]) && types[3] >= 12 && types[3] % 2 == 0;
        if (!message || (!wanted.empty() && (topic < 0 || static_cast<uint64_t>(topic) >= wanted.size() ||
                                             !wanted[static_cast<size_t>(topic)]))) {
            // sqlite reads a whole value, its overflow pages included, whether the row is kept or not.
            if (local < payload) copy(record, local, payload, 0, 0, nullptr);
            return;
        }
        uint64_t take = blob;
        const std::vector<uint8_t>& headed = topics_.headed;
        if (topic >= 0 && static_cast<uint64_t>(topic) < headed.size() && headed[static_cast<size_t>(topic)]) {
            uint8_t head[4] = {};
            const uint64_t seen = std::min<uint64_t>(blob, 4);
            if (blob_at + seen <= local) {
                std::memcpy(head, record + blob_at, seen);
            } else {
                copy(record, local, payload, blob_at, seen, head);
            }
            if (!(seen == 4 && std::memcmp(head, kZstd, 4) == 0)) take = std::min<uint64_t>(blob, topics_.header_bytes);
        }
        const size_t from = got.data->size();
        got.data->resize(from + take);
        copy(record, local, payload, blob_at, take, got.data->data() + from);
        got.topic.push_back(topic);
        got.time.push_back(integer_at(record + header + column_bytes(types[1]), types[2]));
        got.id.push_back(rowid);
        got.start.push_back(static_cast<int64_t>(from));
        got.length.push_back(static_cast<int64_t>(take));
    }

    // Of a payload of ``payload`` bytes, its first ``local`` at ``record``, the ``count`` bytes from
    // ``offset`` into ``into``; the whole overflow chain walked (as sqlite does), its every page checked.
    void copy(const uint8_t* record, uint64_t local, uint64_t payload, uint64_t offset, uint64_t count,
              uint8_t* into) {
        if (count && offset < local) {
            const uint64_t here = std::min(count, local - offset);
            std::memcpy(into, record + offset, here);
            into += here;
            offset += here;
            count -= here;
        }
        if (local >= payload) return;
        const uint64_t room = usable_ - 4;
        uint32_t number = u32(record + local);
        // An overflow page's bytes start at ``first`` of the payload: the pages before ``offset`` and
        // after the bytes asked for are read for their next page's number only.
        for (uint64_t first = local; first < payload; first += room) {
            check_number(number);
            // Each page of a chain belongs to one record: twice the file's pages is more than a
            // file's chains need, even read twice (a record's head, then its bytes).
            if (++overflow_read_ > 2 * uint64_t{pages_} + 64) throw PageError("overflow chains that share pages");
            const uint64_t at = uint64_t{number - 1} * page_size_;
            if (count && offset < first + room) {
                read_at(overflow_.data(), usable_, at);
                const uint64_t here = std::min(count, first + room - offset);
                std::memcpy(into, overflow_.data() + 4 + (offset - first), here);
                into += here;
                offset += here;
                count -= here;
                number = u32(overflow_.data());
            } else {
                uint8_t next[4];
                read_at(next, 4, at);
                number = u32(next);
            }
        }
    }

    int fd_ = -1;
    Topics topics_;
    uint32_t page_size_ = 0, usable_ = 0, pages_ = 0, lock_page_ = 0;
    std::vector<uint8_t> visited_;  // a bit a page: the tree's pages entered
    std::vector<uint8_t> chunk_, overflow_;
    uint64_t overflow_read_ = 0;  // overflow pages read so far
    uint32_t chunk_first_ = 0, chunk_pages_ = 0;
    std::vector<Level> levels_;
    uint32_t leaf_ = 0, cells_ = 0, cell_ = 0;  // the leaf being read, its cells and the next one
};

}  // namespace db3
