// The Modbus map: configuration errors located, values decoded and encoded by
// type, word order, scale/offset and enumeration, reads batched.
#include <catch2/catch.hpp>

#include "modbus/modbus_map.hpp"

using namespace nclink;
using namespace nclink::modbus;

namespace {

Config parse_ok(const char* text) {
    auto c = parse_config(Json::parse(text));
    INFO((c.ok() ? std::string() : c.error().message));
    REQUIRE(c.ok());
    return c.value();
}

std::string parse_error(const char* text) {
    auto c = parse_config(Json::parse(text));
    REQUIRE_FALSE(c.ok());
    return c.error().message;
}

}  // namespace

TEST_CASE("a map with defaults and every table reads back") {
    Config c = parse_ok(R"({"host":"10.0.0.5","points":{
        "a":{"table":"holding","address":0},
        "b":{"table":"input_register","address":3,"type":"int32","word_order":"little","scale":0.1},
        "c":{"table":"coil","address":7},
        "d":{"table":"discrete_input","address":1}}})");
    CHECK(c.host == "10.0.0.5");
    CHECK(c.port == 502);
    CHECK(c.unit_id == 1);
    REQUIRE(c.points.size() == 4);
    const Point* b = c.find("b");
    REQUIRE(b);
    CHECK(b->table == Table::input_register);
    CHECK(b->type == RegType::int32);
    CHECK(b->width() == 2);
    CHECK(b->word_order == WordOrder::little);
    CHECK(c.find("c")->type == RegType::boolean);
    CHECK(c.find("a")->type == RegType::uint16);
    CHECK(c.find("zzz") == nullptr);
}

TEST_CASE("configuration mistakes name where they are") {
    CHECK_THAT(parse_error(R"({"points":{}})"), Catch::Contains("points: missing"));
    CHECK_THAT(parse_error(R"({"points":{"a":{"table":"holdin","address":0}}})"),
               Catch::Contains("points/a/table: unknown table \"holdin\""));
    CHECK_THAT(parse_error(R"({"points":{"a":{"table":"coil"}}})"), Catch::Contains("points/a/address: missing"));
    CHECK_THAT(parse_error(R"({"points":{"a":{"table":"coil","address":70000}}})"),
               Catch::Contains("points/a/address: must be an integer in 0..65535"));
    CHECK_THAT(parse_error(R"({"points":{"a":{"table":"coil","address":1,"type":"int16"}}})"),
               Catch::Contains("a coil or discrete input is a bool"));
    CHECK_THAT(parse_error(R"({"points":{"a":{"table":"holding","address":1,"scale":0}}})"),
               Catch::Contains("points/a/scale: must not be 0"));
    CHECK_THAT(parse_error(R"({"points":{"a":{"table":"holding","address":65535,"type":"int32"}}})"),
               Catch::Contains("runs past address 65535"));
    CHECK_THAT(parse_error(R"({"port":"502","points":{"a":{"table":"coil","address":1}}})"),
               Catch::Contains("port: must be a number"));
    CHECK_THAT(parse_error(R"({"hots":"x","points":{"a":{"table":"coil","address":1}}})"),
               Catch::Contains("/hots: unknown key (known: host"));
    CHECK_THAT(parse_error(R"({"points":{"a":{"table":"holding","address":1,"enum":{"x":"free"}}}})"),
               Catch::Contains("points/a/enum/x: key must be an integer"));
    CHECK_THAT(parse_error(R"({"points":{"a":{"table":"holding","address":1,"type":"float32","enum":{"1":"free"}}}})"),
               Catch::Contains("needs an integer type"));
    CHECK_THAT(parse_error(R"({"backoff_ms":{"min":500,"max":100},"points":{"a":{"table":"coil","address":1}}})"),
               Catch::Contains("max is smaller than min"));
    CHECK_THAT(parse_error(R"([1])"), Catch::Contains("must be an object"));
}

TEST_CASE("decoding: types, word order, scale and offset") {
    Point p;
    p.type = RegType::int16;
    const std::uint16_t minus_two[] = {0xFFFE};
    CHECK(decode(p, minus_two).value() == -2);

    p.type = RegType::uint32;
    const std::uint16_t big[] = {0x0001, 0x0002};
    CHECK(decode(p, big).value() == 0x00010002);
    p.word_order = WordOrder::little;
    CHECK(decode(p, big).value() == 0x00020001);

    p.type = RegType::float32;
    p.word_order = WordOrder::big;
    const std::uint16_t one_and_half[] = {0x3FC0, 0x0000};  // 1.5f
    CHECK(decode(p, one_and_half).value() == 1.5);

    p.type = RegType::int32;
    p.scale = 0.001;
    p.offset = 10;
    const std::uint16_t value[] = {0x0000, 0x3039};  // 12345
    CHECK(decode(p, value).value().get<double>() == Approx(22.345));

    p = Point{};
    p.type = RegType::float64;
    const std::uint16_t pi[] = {0x4009, 0x21FB, 0x5444, 0x2D18};
    CHECK(decode(p, pi).value().get<double>() == Approx(3.141592653589793));
    const std::uint16_t nan[] = {0x7FF8, 0, 0, 0};
    CHECK(decode(p, nan).value().is_null());

    p = Point{};
    p.type = RegType::int64;
    const std::uint16_t minus_one[] = {0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF};
    CHECK(decode(p, minus_one).value() == -1);
}

TEST_CASE("an enumeration turns raw values into words, and an unknown one is an error") {
    Config c = parse_ok(R"({"points":{"status":{"table":"holding","address":0,"enum":{"0":"free","1":"running","2":"holding"}},
                                      "door":{"table":"coil","address":0,"enum":{"0":"closed","1":"open"}}}})");
    const Point& status = *c.find("status");
    const std::uint16_t one[] = {1};
    CHECK(decode(status, one).value() == "running");
    const std::uint16_t nine[] = {9};
    auto bad = decode(status, nine);
    REQUIRE_FALSE(bad.ok());
    CHECK_THAT(bad.error().message, Catch::Contains("raw value 9 is not in the map's enum"));
    CHECK(decode_bit(*c.find("door"), true) == "open");
    CHECK(encode(status, Json("holding")).value().words == std::vector<std::uint16_t>{2});
    CHECK(encode(status, Json("flying")).error().code == ErrorCode::out_of_range);
}

TEST_CASE("text points send numbers as decimal text and parse a Set's text back") {
    Config c = parse_ok(R"({"points":{"parts":{"table":"holding","address":0,"type":"uint32","text":true},
                                      "load":{"table":"holding","address":2,"scale":0.5,"text":true}}})");
    const std::uint16_t seventeen[] = {0, 17};
    CHECK(decode(*c.find("parts"), seventeen).value() == "17");
    const std::uint16_t three[] = {3};
    CHECK(decode(*c.find("load"), three).value() == "1.5");
    CHECK(encode(*c.find("parts"), Json("42")).value().words == std::vector<std::uint16_t>{0, 42});
    CHECK(encode(*c.find("parts"), Json("4x")).error().code == ErrorCode::value_type);
    CHECK_THAT(parse_error(R"({"points":{"a":{"table":"holding","address":0,"text":"yes"}}})"), Catch::Contains("points/a/text"));
    CHECK_THAT(parse_error(R"({"points":{"a":{"table":"holding","address":0,"enum":{"0":"x"},"text":true}}})"),
               Catch::Contains("cannot be combined with enum"));
}

TEST_CASE("encoding is decoding's inverse and checks the raw range") {
    Point p;
    p.type = RegType::int32;
    p.word_order = WordOrder::little;
    p.scale = 0.01;
    auto e = encode(p, Json(-1.5));
    REQUIRE(e.ok());
    REQUIRE(e.value().words.size() == 2);
    CHECK(decode(p, e.value().words.data()).value().get<double>() == Approx(-1.5));

    p = Point{};
    p.type = RegType::uint16;
    CHECK(encode(p, Json(65535)).value().words == std::vector<std::uint16_t>{0xFFFF});
    CHECK(encode(p, Json(65536)).error().code == ErrorCode::out_of_range);
    CHECK(encode(p, Json(-1)).error().code == ErrorCode::out_of_range);
    CHECK(encode(p, Json("7")).error().code == ErrorCode::value_type);

    p.type = RegType::float32;
    e = encode(p, Json(2.25));
    CHECK(decode(p, e.value().words.data()).value() == 2.25);

    p.table = Table::coil;
    p.type = RegType::boolean;
    CHECK(encode(p, Json(true)).value().bit);
    CHECK_FALSE(encode(p, Json(0)).value().bit);
    CHECK(encode(p, Json(2)).error().code == ErrorCode::out_of_range);
}

TEST_CASE("reads are batched per table within the gap and the protocol's limits") {
    Config c = parse_ok(R"({"points":{
        "a":{"table":"holding","address":0},
        "b":{"table":"holding","address":5,"type":"float32"},
        "c":{"table":"holding","address":40},
        "d":{"table":"input","address":5},
        "e":{"table":"coil","address":3},
        "f":{"table":"coil","address":1000}}})");
    std::vector<const Point*> points{c.find("c"), c.find("a"), nullptr, c.find("b"), c.find("d"), c.find("e"), c.find("f")};
    auto spans = plan_reads(points, 8);
    // a+b in one request (gap 4 <= 8), c alone, d alone, e and f within the
    // 2000-bit limit but 996 apart (> gap): two requests.
    REQUIRE(spans.size() == 5);
    CHECK(spans[0].table == Table::coil);
    CHECK(spans[0].start == 3);
    CHECK(spans[1].start == 1000);
    CHECK(spans[2].table == Table::holding_register);
    CHECK(spans[2].start == 0);
    CHECK(spans[2].count == 7);  // 0..6: a, gap, b (2 registers at 5)
    CHECK(spans[2].members == std::vector<std::size_t>{1, 3});
    CHECK(spans[3].start == 40);
    CHECK(spans[4].table == Table::input_register);

    // 125 registers at most in one request.
    std::vector<Point> many(130);
    std::vector<const Point*> refs;
    for (unsigned i = 0; i < many.size(); ++i) {
        many[i].address = static_cast<std::uint16_t>(i);
        refs.push_back(&many[i]);
    }
    spans = plan_reads(refs, 0);
    REQUIRE(spans.size() == 2);
    CHECK(spans[0].count == 125);
    CHECK(spans[1].count == 5);
}

TEST_CASE("an RTU map names a serial line: defaults are Modbus over Serial Line's 19200 8E1") {
    Config c = parse_ok(R"({"device":"/dev/ttyUSB0","slave_id":7,"points":{"a":{"table":"holding","address":0}}})");
    REQUIRE(c.serial);
    CHECK(c.serial->device == "/dev/ttyUSB0");
    CHECK(c.serial->baud == 19200);
    CHECK(c.serial->parity == 'E');
    CHECK(c.serial->data_bits == 8);
    CHECK(c.serial->stop_bits == 1);
    CHECK(c.serial->frame_gap.count() == 0);
    CHECK(c.unit_id == 7);
    CHECK(c.byte_timeout.count() == 100);
    CHECK(c.endpoint() == "rtu /dev/ttyUSB0 slave 7");
    CHECK(c.serial->describe() == "/dev/ttyUSB0 19200 8E1");

    c = parse_ok(R"({"device":"/dev/ttyS1","baud":9600,"parity":"N","data_bits":8,"stop_bits":2,"unit_id":3,
                     "byte_timeout_ms":20,"frame_gap_us":5000,"points":{"a":{"table":"coil","address":0}}})");
    CHECK(c.serial->baud == 9600);
    CHECK(c.serial->parity == 'N');
    CHECK(c.serial->stop_bits == 2);
    CHECK(c.serial->frame_gap.count() == 5000);
    CHECK(c.byte_timeout.count() == 20);
    CHECK(c.unit_id == 3);
    CHECK(parse_ok(R"({"device":"/dev/x","parity":"odd","points":{"a":{"table":"coil","address":0}}})").serial->parity == 'O');

    // A TCP map stays TCP.
    CHECK_FALSE(parse_ok(R"({"host":"10.0.0.5","points":{"a":{"table":"coil","address":0}}})").serial);
}

TEST_CASE("the silence between RTU frames is 3.5 characters, 1.75 ms above 19200 baud") {
    SerialLine line;
    line.baud = 19200;  // 8E1: 11 bits a character
    CHECK(line.minimum_frame_gap().count() == 2006);
    line.baud = 9600;
    line.parity = 'N';  // 8N1: 10 bits
    CHECK(line.minimum_frame_gap().count() == 3646);
    line.baud = 115200;
    CHECK(line.minimum_frame_gap().count() == 1750);
}

TEST_CASE("RTU configuration mistakes are located") {
    CHECK_THAT(parse_error(R"({"device":"/dev/x","host":"h","points":{"a":{"table":"coil","address":0}}})"),
               Catch::Contains("host: a map with \"device\" (Modbus RTU) has no host or port"));
    CHECK_THAT(parse_error(R"({"baud":9600,"points":{"a":{"table":"coil","address":0}}})"),
               Catch::Contains("baud: only for Modbus RTU"));
    CHECK_THAT(parse_error(R"({"device":"","points":{"a":{"table":"coil","address":0}}})"), Catch::Contains("device: must be"));
    CHECK_THAT(parse_error(R"({"device":"/dev/x","parity":"X","points":{"a":{"table":"coil","address":0}}})"),
               Catch::Contains("parity: must be \"N\", \"E\" or \"O\""));
    CHECK_THAT(parse_error(R"({"device":"/dev/x","data_bits":9,"points":{"a":{"table":"coil","address":0}}})"),
               Catch::Contains("data_bits: must be an integer in 5..8"));
    CHECK_THAT(parse_error(R"({"device":"/dev/x","stop_bits":3,"points":{"a":{"table":"coil","address":0}}})"),
               Catch::Contains("stop_bits"));
    // Slave address 0 is a broadcast no slave answers; 248..255 are reserved.
    CHECK_THAT(parse_error(R"({"device":"/dev/x","slave_id":0,"points":{"a":{"table":"coil","address":0}}})"),
               Catch::Contains("slave_id: must be an integer in 1..247"));
    CHECK_THAT(parse_error(R"({"device":"/dev/x","unit_id":248,"points":{"a":{"table":"coil","address":0}}})"),
               Catch::Contains("unit_id: must be an integer in 1..247"));
    CHECK_THAT(parse_error(R"({"device":"/dev/x","unit_id":1,"slave_id":2,"points":{"a":{"table":"coil","address":0}}})"),
               Catch::Contains("slave_id: names the same as unit_id"));
    CHECK_THAT(parse_error(R"({"device":"/dev/x","frame_gap_us":100,"points":{"a":{"table":"coil","address":0}}})"),
               Catch::Contains("frame_gap_us: below 3.5 character times at 19200 baud (2006 us"));
    CHECK_THAT(parse_error(R"({"device":"/dev/x","byte_timeout_ms":0,"points":{"a":{"table":"coil","address":0}}})"),
               Catch::Contains("byte_timeout_ms"));
    // TCP keeps its unit id range.
    CHECK(parse_ok(R"({"host":"h","unit_id":0,"points":{"a":{"table":"coil","address":0}}})").unit_id == 0);
}
