// tftools.sources.bag.rosbag2._sqlite: a query's rows read through sqlite's C API, fetch after fetch,
// into arrays and one byte buffer (Python's sqlite3 would build a tuple and a bytes object a row).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <sqlite3.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace nb = nanobind;
using namespace nb::literals;

namespace {

template <typename T>
using Output = nb::ndarray<nb::numpy, T>;

template <typename T>
Output<T> owned(std::vector<T>&& values) {
    auto* held = new std::vector<T>(std::move(values));
    nb::capsule owner(held, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
    return Output<T>(held->data(), {held->size()}, owner);
}

// ``bytes`` as a numpy array that shares them.
Output<uint8_t> shared(const std::shared_ptr<std::vector<uint8_t>>& bytes) {
    auto* held = new std::shared_ptr<std::vector<uint8_t>>(bytes);
    nb::capsule owner(held, [](void* p) noexcept { delete static_cast<std::shared_ptr<std::vector<uint8_t>>*>(p); });
    return Output<uint8_t>(bytes->data(), {bytes->size()}, owner);
}

struct SqliteError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Columns of the rows of one fetch: each row's integers, where its blob starts in ``data`` and its length.
struct Fetched {
    std::vector<int64_t> topic, time, id, start, length;
    std::vector<uint8_t>* data;
};

using FetchedArrays = std::tuple<Output<int64_t>, Output<int64_t>, Output<int64_t>, Output<int64_t>,
                                 Output<int64_t>, Output<uint8_t>>;

// The rows of ``SELECT topic, time, id, blob ...`` on a database opened read-only; a row whose topic
// or time is not an integer or whose blob is not a blob is not a message: skipped.
class Messages {
   public:
    Messages(const std::string& uri, const std::string& query) {
        sqlite3* db = nullptr;
        // NOMUTEX: the connection is this reader's alone, read by one thread: no lock around every call.
        const int flags = SQLITE_OPEN_READONLY | SQLITE_OPEN_URI | SQLITE_OPEN_NOMUTEX;
        const int opened = sqlite3_open_v2(uri.c_str(), &db, flags, nullptr);
        db_.reset(db);  // closed when this throws, as when it is let go
        if (opened != SQLITE_OK) fail();
        // A file cut short says it has more pages than it holds; sqlite then refuses it whole
        // unless the schema is "writable" (a flag of this read-only connection, nothing written).
        if (sqlite3_exec(db, "PRAGMA writable_schema=ON", nullptr, nullptr, nullptr) != SQLITE_OK) fail();
        sqlite3_stmt* statement = nullptr;
        const int prepared = sqlite3_prepare_v2(db, query.c_str(), -1, &statement, nullptr);
        statement_.reset(statement);
        if (prepared != SQLITE_OK) fail();
        if (sqlite3_column_count(statement) != 4) throw nb::value_error("Messages: the query must give 4 columns");
    }

    // The next rows, up to ``rows`` of them or until ``bytes`` of blobs are held; none at the end.
    FetchedArrays fetch(int64_t rows, int64_t bytes) {
        // The bytes of the fetch before are filled again once Python has let go of them: their
        // pages are already the process's (new ones are faulted in page by page).
        if (data_.use_count() != 1) data_ = std::make_shared<std::vector<uint8_t>>();
        data_->clear();
        data_->reserve(static_cast<size_t>(std::min<int64_t>(bytes, 1 << 22)) + 65536);
        Fetched got{{}, {}, {}, {}, {}, data_.get()};
        std::string error;
        {
            nb::gil_scoped_release unlocked;
            error = step(got, rows, bytes);
        }
        if (!error.empty()) throw SqliteError(error);
        return {owned(std::move(got.topic)), owned(std::move(got.time)),   owned(std::move(got.id)),
                owned(std::move(got.start)), owned(std::move(got.length)), shared(data_)};
    }

   private:
    // Rows into ``got``; sqlite's error, or "".
    std::string step(Fetched& got, int64_t rows, int64_t bytes) {
        sqlite3_stmt* statement = statement_.get();
        while (!done_ && static_cast<int64_t>(got.topic.size()) < rows &&
               static_cast<int64_t>(got.data->size()) < bytes) {
            const int result = sqlite3_step(statement);
            if (result != SQLITE_ROW) {
                done_ = true;
                if (result == SQLITE_DONE) break;
                return sqlite3_errmsg(db_.get());
            }
            if (sqlite3_column_type(statement, 0) != SQLITE_INTEGER ||
                sqlite3_column_type(statement, 1) != SQLITE_INTEGER ||
                sqlite3_column_type(statement, 3) != SQLITE_BLOB) {
                continue;
            }
            const auto* blob = static_cast<const uint8_t*>(sqlite3_column_blob(statement, 3));
            const auto length = static_cast<size_t>(sqlite3_column_bytes(statement, 3));
            got.topic.push_back(sqlite3_column_int64(statement, 0));
            got.time.push_back(sqlite3_column_int64(statement, 1));
            got.id.push_back(sqlite3_column_int64(statement, 2));
            got.start.push_back(static_cast<int64_t>(got.data->size()));
            got.length.push_back(static_cast<int64_t>(length));
            got.data->insert(got.data->end(), blob, blob + length);
        }
        return {};
    }

    [[noreturn]] void fail() const { throw SqliteError(db_ ? sqlite3_errmsg(db_.get()) : "out of memory"); }

    struct Close {
        void operator()(sqlite3* db) const { sqlite3_close(db); }
        void operator()(sqlite3_stmt* statement) const { sqlite3_finalize(statement); }
    };
    // Declared in this order so that the statement is finalized before its database is closed.
    std::unique_ptr<sqlite3, Close> db_;
    std::unique_ptr<sqlite3_stmt, Close> statement_;
    std::shared_ptr<std::vector<uint8_t>> data_;  // the blobs of the latest fetch
    bool done_ = false;
};

}  // namespace

NB_MODULE(_sqlite, m) {
    m.doc() = "A query's rows read through sqlite's C API into arrays, fetch after fetch.";
    nb::exception<SqliteError>(m, "SqliteError", nb::module_::import_("sqlite3").attr("DatabaseError").ptr());
    nb::class_<Messages>(m, "Messages")
        .def(nb::init<const std::string&, const std::string&>(), "uri"_a, "query"_a)
        .def("fetch", &Messages::fetch, "rows"_a, "bytes"_a);
}
