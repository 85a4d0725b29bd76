// tftools.sources.bag.rosbag2._sqlite: one read-only connection to a .db3 file (``Database``), serving its
// small tables' queries as tuples and its messages through sqlite's C API, fetch after fetch, into arrays
// and one byte buffer (Python's sqlite3 would build a tuple and a bytes object a row); and the messages
// table read from its pages (``TablePages``, db3_pages.hpp) into the same arrays.
#include <Python.h>
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>
#include <sqlite3.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "db3_pages.hpp"

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

using db3::Fetched;

using FetchedArrays = std::tuple<Output<int64_t>, Output<int64_t>, Output<int64_t>, Output<int64_t>,
                                 Output<int64_t>, Output<uint8_t>>;

struct Close {
    void operator()(sqlite3* db) const { sqlite3_close(db); }
    void operator()(sqlite3_stmt* statement) const { sqlite3_finalize(statement); }
};

// A connection shared by its database and the message queries on it: closed when the last lets it go.
using Connection = std::shared_ptr<sqlite3>;

[[noreturn]] void fail(sqlite3* db) { throw SqliteError(db ? sqlite3_errmsg(db) : "out of memory"); }

std::unique_ptr<sqlite3_stmt, Close> prepare(const Connection& db, const std::string& query) {
    if (!db) throw SqliteError("the database is closed");
    sqlite3_stmt* statement = nullptr;
    const int prepared = sqlite3_prepare_v2(db.get(), query.c_str(), -1, &statement, nullptr);
    std::unique_ptr<sqlite3_stmt, Close> held(statement);
    if (prepared != SQLITE_OK) fail(db.get());
    return held;
}

// Whether each topic id is among ``topics`` (an empty list where none are).
std::vector<uint8_t> flags(const std::vector<int64_t>& topics) {
    constexpr int64_t kMaxTopic = int64_t{1} << 24;
    std::vector<uint8_t> listed;
    for (const int64_t topic : topics) {
        if (topic < 0 || topic > kMaxTopic) throw nb::value_error("a topic id out of range");
        if (static_cast<size_t>(topic) >= listed.size()) listed.resize(static_cast<size_t>(topic) + 1);
        listed[static_cast<size_t>(topic)] = 1;
    }
    return listed;
}

// The byte buffer that one fetch after another fills, and each fetch's arrays.
class Batches {
   public:
    // The rows ``step`` puts into a fetch's columns, the GIL let go meanwhile.
    template <typename Step>
    FetchedArrays fetch(int64_t bytes, Step&& step) {
        // The bytes of the fetch before are filled again once Python has let go of them: their
        // pages are already the process's (new ones are faulted in page by page).
        if (data_.use_count() != 1) data_ = std::make_shared<std::vector<uint8_t>>();
        data_->clear();
        data_->reserve(static_cast<size_t>(std::min<int64_t>(bytes, 1 << 22)) + 65536);
        Fetched got{{}, {}, {}, {}, {}, data_.get()};
        {
            nb::gil_scoped_release unlocked;
            step(got);
        }
        return {owned(std::move(got.topic)), owned(std::move(got.time)),   owned(std::move(got.id)),
                owned(std::move(got.start)), owned(std::move(got.length)), shared(data_)};
    }

   private:
    std::shared_ptr<std::vector<uint8_t>> data_ = std::make_shared<std::vector<uint8_t>>();
};

// The rows of ``SELECT topic, time, id, blob ...`` on a database opened read-only; a row whose topic
// or time is not an integer or whose blob is not a blob is not a message, nor is a row of a topic not
// among those listed (where some are): skipped.
class Messages {
   public:
    Messages(Connection db, const std::string& query, const std::vector<int64_t>& topics)
        : db_(std::move(db)), statement_(prepare(db_, query)) {
        wanted_ = flags(topics);
        if (sqlite3_column_count(statement_.get()) != 4) {
            throw nb::value_error("Messages: the query must give 4 columns");
        }
    }

    // The next rows, up to ``rows`` of them or until ``bytes`` of blobs are held; none at the end.
    FetchedArrays fetch(int64_t rows, int64_t bytes) {
        return batches_.fetch(bytes, [&](Fetched& got) {
            const std::string error = step(got, rows, bytes);
            if (!error.empty()) throw SqliteError(error);
        });
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
            // Each column's value once (a column call of sqlite's API costs a value's reading and the
            // statement's checks: twice as many of them as values read).
            sqlite3_value* const topic = sqlite3_column_value(statement, 0);
            sqlite3_value* const time = sqlite3_column_value(statement, 1);
            sqlite3_value* const payload = sqlite3_column_value(statement, 3);
            if (sqlite3_value_type(topic) != SQLITE_INTEGER || sqlite3_value_type(time) != SQLITE_INTEGER ||
                sqlite3_value_type(payload) != SQLITE_BLOB) {
                continue;
            }
            const int64_t topic_id = sqlite3_value_int64(topic);
            if (!wanted_.empty() &&
                (topic_id < 0 || static_cast<uint64_t>(topic_id) >= wanted_.size() || !wanted_[topic_id])) {
                continue;
            }
            const auto* blob = static_cast<const uint8_t*>(sqlite3_value_blob(payload));
            const auto length = static_cast<size_t>(sqlite3_value_bytes(payload));
            got.topic.push_back(topic_id);
            got.time.push_back(sqlite3_value_int64(time));
            got.id.push_back(sqlite3_column_int64(statement, 2));
            got.start.push_back(static_cast<int64_t>(got.data->size()));
            got.length.push_back(static_cast<int64_t>(length));
            got.data->insert(got.data->end(), blob, blob + length);
        }
        return {};
    }

    // Declared in this order so that the statement is finalized before its database is let go.
    Connection db_;
    std::unique_ptr<sqlite3_stmt, Close> statement_;
    // Whether each topic id is wanted (none listed: every topic): sqlite's own ``topic_id IN (...)``
    // costs more than this test.
    std::vector<uint8_t> wanted_;
    Batches batches_;
    bool done_ = false;
};

// The messages table read from its pages (db3_pages.hpp): the rows of the query ``Messages`` serves
// without a window, of the topics ``wanted`` (those of ``headed`` cut to ``header_bytes`` but where
// compressed); ``PageError`` where the pages are not what the reader reads.
class TablePages {
   public:
    TablePages(const std::string& path, uint32_t root, const std::vector<int64_t>& wanted,
               const std::vector<int64_t>& headed, size_t header_bytes)
        : pages_(path, root, db3::Topics{flags(wanted), flags(headed), header_bytes}) {}

    FetchedArrays fetch(int64_t rows, int64_t bytes) {
        return batches_.fetch(bytes, [&](Fetched& got) {
            if (!done_) done_ = !pages_.step(got, rows, bytes);
        });
    }

   private:
    db3::TablePages pages_;
    Batches batches_;
    bool done_ = false;
};

// A column's value as Python's sqlite3 gives it; text not in UTF-8 decoded with replacement characters.
nb::object value(sqlite3_stmt* statement, int column) {
    switch (sqlite3_column_type(statement, column)) {
        case SQLITE_INTEGER:
            return nb::int_(sqlite3_column_int64(statement, column));
        case SQLITE_FLOAT:
            return nb::float_(sqlite3_column_double(statement, column));
        case SQLITE_TEXT: {
            const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(statement, column));
            const auto length = static_cast<Py_ssize_t>(sqlite3_column_bytes(statement, column));
            return nb::steal(PyUnicode_DecodeUTF8(text, length, "replace"));
        }
        case SQLITE_BLOB: {
            const void* blob = sqlite3_column_blob(statement, column);
            return nb::bytes(static_cast<const char*>(blob), static_cast<size_t>(sqlite3_column_bytes(statement, column)));
        }
        default:
            return nb::none();
    }
}

// One read-only connection to a database: its small queries answered as lists of tuples, its messages
// read by ``messages``; closed by ``close`` (the message queries still open keep it until they go).
class Database {
   public:
    explicit Database(const std::string& uri) {
        sqlite3* db = nullptr;
        // NOMUTEX: the connection is this reader's alone, used by one thread at a time: no lock around every call.
        const int flags = SQLITE_OPEN_READONLY | SQLITE_OPEN_URI | SQLITE_OPEN_NOMUTEX;
        const int opened = sqlite3_open_v2(uri.c_str(), &db, flags, nullptr);
        db_ = Connection(db, Close{});  // closed when this throws, as when it is let go
        if (opened != SQLITE_OK) fail(db);
        // A file cut short says it has more pages than it holds; sqlite then refuses it whole
        // unless the schema is "writable" (a flag of this read-only connection, nothing written).
        if (sqlite3_exec(db, "PRAGMA writable_schema=ON", nullptr, nullptr, nullptr) != SQLITE_OK) fail(db);
    }

    nb::list rows(const std::string& query) {
        auto statement = prepare(db_, query);
        const int columns = sqlite3_column_count(statement.get());
        nb::list found;
        int result;
        while ((result = sqlite3_step(statement.get())) == SQLITE_ROW) {
            nb::list row;
            for (int c = 0; c < columns; ++c) row.append(value(statement.get(), c));
            found.append(nb::tuple(row));
        }
        if (result != SQLITE_DONE) fail(db_.get());
        return found;
    }

    Messages messages(const std::string& query, const std::vector<int64_t>& topics) {
        return Messages(db_, query, topics);
    }

    void close() { db_.reset(); }

   private:
    Connection db_;
};

}  // namespace

NB_MODULE(_sqlite, m) {
    m.doc() = "One read-only sqlite connection: small queries as tuples, messages into arrays fetch after fetch.";
    nb::exception<SqliteError>(m, "SqliteError", nb::module_::import_("sqlite3").attr("DatabaseError").ptr());
    nb::exception<db3::PageError>(m, "PageError");
    nb::class_<TablePages>(m, "TablePages")
        .def(nb::init<const std::string&, uint32_t, const std::vector<int64_t>&, const std::vector<int64_t>&, size_t>(),
             "path"_a, "root"_a, "wanted"_a, "headed"_a, "header_bytes"_a)
        .def("fetch", &TablePages::fetch, "rows"_a, "bytes"_a);
    nb::class_<Messages>(m, "Messages").def("fetch", &Messages::fetch, "rows"_a, "bytes"_a);
    nb::class_<Database>(m, "Database")
        .def(nb::init<const std::string&>(), "uri"_a)
        .def("rows", &Database::rows, "query"_a)
        .def("messages", &Database::messages, "query"_a, "topics"_a = std::vector<int64_t>{})
        .def("close", &Database::close);
}
