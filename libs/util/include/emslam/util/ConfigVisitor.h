// SPDX-License-Identifier: BSD-3-Clause
#pragma once

#include <mrpt/config/CConfigFileBase.h>

#include <string>
#include <utility>

namespace emslam::util
{
/** Walks the fields of one parameter struct for both loading and saving, so
 * that each field is listed once, with its INI key and its documentation,
 * and load and save cannot drift apart (Basalt's single serialize()).
 *
 * A struct writes one function that names every field:
 * \code
 * void visit(TParameters& p, util::ConfigVisitor& v)
 * {
 *     v.field("cell_size", p.cell_size, "[m] voxel edge");
 *     v.text("energy", p.energy, toString, parseEnergy, "structured | ...");
 * }
 * void TParameters::loadFromConfigFile(const CConfigFileBase& c, const std::string& s)
 * {
 *     util::loadByVisit(*this, c, s, visit);
 *     validate();
 * }
 * void TParameters::saveToConfigFile(CConfigFileBase& c, const std::string& s) const
 * {
 *     util::saveByVisit(*this, c, s, visit);
 * }
 * \endcode
 *
 * Loading reads each key as MRPT_LOAD_CONFIG_VAR does, with the field's
 * current value as the default. Saving writes as MRPT_SAVE_CONFIG_VAR (no
 * documentation) or MRPT_SAVE_CONFIG_VAR_COMMENT (padded, with the
 * documentation as a trailing comment) does.
 * \ingroup emslam_util_grp */
class ConfigVisitor
{
public:
    /** A visitor that reads `section` of `in` into the fields. */
    static ConfigVisitor loader(const mrpt::config::CConfigFileBase& in, std::string section)
    {
        return ConfigVisitor(&in, nullptr, std::move(section));
    }
    /** A visitor that writes the fields into `section` of `out`. */
    static ConfigVisitor saver(mrpt::config::CConfigFileBase& out, std::string section)
    {
        return ConfigVisitor(nullptr, &out, std::move(section));
    }

    /** True for a loader(), false for a saver(). */
    bool loading() const { return m_in != nullptr; }
    /** The INI section visited. */
    const std::string& section() const { return m_section; }
    /** The file read (only while loading()). */
    const mrpt::config::CConfigFileBase& input() const { return *m_in; }

    /** One field stored as itself: bool, int, float, double or std::string. */
    template <class T>
    void field(const std::string& key, T& value, const std::string& doc = {})
    {
        if (m_in != nullptr)
        {
            value = read(key, value);
        }
        else
        {
            write(key, value, doc);
        }
    }

    /** One field stored as text (an enum, a number with its own format):
     * saving writes `to_text(value)`; loading sets `value =
     * from_text(text)` if the key is there and leaves it alone otherwise. */
    template <class T, class ToText, class FromText>
    void text(
        const std::string& key,
        T& value,
        ToText&& to_text,
        FromText&& from_text,
        const std::string& doc = {})
    {
        if (m_in != nullptr)
        {
            if (m_in->keyExists(m_section, key))
            {
                value = from_text(m_in->read_string(m_section, key, {}));
            }
        }
        else
        {
            write(key, std::string(to_text(value)), doc);
        }
    }

private:
    ConfigVisitor(
        const mrpt::config::CConfigFileBase* in,
        mrpt::config::CConfigFileBase* out,
        std::string section)
        : m_in(in), m_out(out), m_section(std::move(section))
    {
    }

    bool read(const std::string& key, bool v) const { return m_in->read_bool(m_section, key, v); }
    int read(const std::string& key, int v) const { return m_in->read_int(m_section, key, v); }
    float read(const std::string& key, float v) const
    {
        return m_in->read_float(m_section, key, v);
    }
    double read(const std::string& key, double v) const
    {
        return m_in->read_double(m_section, key, v);
    }
    std::string read(const std::string& key, const std::string& v) const
    {
        return m_in->read_string(m_section, key, v);
    }

    template <class T>
    void write(const std::string& key, const T& value, const std::string& doc)
    {
        if (doc.empty())
        {
            m_out->write(m_section, key, value);
        }
        else
        {
            m_out->write(
                m_section, key, value, mrpt::config::MRPT_SAVE_NAME_PADDING(),
                mrpt::config::MRPT_SAVE_VALUE_PADDING(), doc);
        }
    }

    const mrpt::config::CConfigFileBase* m_in;
    mrpt::config::CConfigFileBase* m_out;
    std::string m_section;
};

/** Loads `p` from `section` of `in` through `visit(p, loader)`. */
template <class P>
void loadByVisit(
    P& p,
    const mrpt::config::CConfigFileBase& in,
    const std::string& section,
    void (*visit)(P&, ConfigVisitor&))
{
    auto v = ConfigVisitor::loader(in, section);
    visit(p, v);
}

/** Saves `p` into `section` of `out` through `visit(copy, saver)`. The walk
 * takes non-const fields (the same function loads), so it walks a copy. */
template <class P>
void saveByVisit(
    const P& p,
    mrpt::config::CConfigFileBase& out,
    const std::string& section,
    void (*visit)(P&, ConfigVisitor&))
{
    P copy = p;
    auto v = ConfigVisitor::saver(out, section);
    visit(copy, v);
}

}  // namespace emslam::util
