#include "core/haptics/input_device.h"

#include <algorithm>
#include <cassert>

namespace softtouch {

NullDevice::NullDevice() {
    m_info.name = "Null device";
}

DeviceSample NullDevice::read(double seconds) {
    DeviceSample sample;
    sample.time = seconds;
    return sample;
}

void NullDevice::sendForce(const Vec3&) {}

DeviceInfo scriptedDeviceInfo() {
    DeviceInfo info;
    info.name = "Scripted device";
    info.degreesOfFreedom = 3;
    info.workspaceMin = Vec3::Constant(-0.1);
    info.workspaceMax = Vec3::Constant(0.1);
    info.maxForceN = 3.3;
    info.stableStiffnessNPerM = 1000.0;
    info.buttons = 2;
    info.forceFeedback = true;
    return info;
}

TrajectoryDevice::TrajectoryDevice(std::vector<DeviceSample> samples, DeviceInfo info)
    : m_samples(std::move(samples)), m_info(std::move(info)) {
    assert(std::is_sorted(m_samples.begin(), m_samples.end(),
                          [](const DeviceSample& a, const DeviceSample& b) { return a.time < b.time; }));
}

DeviceSample TrajectoryDevice::read(double seconds) {
    DeviceSample out;
    if (m_samples.empty()) {
        out.time = seconds;
        return out;
    }
    if (seconds <= m_samples.front().time) {
        out = m_samples.front();
        out.time = seconds;
        return out;
    }
    if (seconds >= m_samples.back().time) {
        out = m_samples.back();
        out.time = seconds;
        return out;
    }
    // Reads usually move forward by one tick: walk from the cursor, fall back to a binary search.
    if (m_cursor >= m_samples.size() || m_samples[m_cursor].time > seconds) m_cursor = 0;
    while (m_cursor + 1 < m_samples.size() && m_samples[m_cursor + 1].time <= seconds) {
        if (m_cursor + 64 < m_samples.size() && m_samples[m_cursor + 64].time <= seconds) {
            auto it = std::upper_bound(m_samples.begin() + std::ptrdiff_t(m_cursor), m_samples.end(), seconds,
                                       [](double t, const DeviceSample& s) { return t < s.time; });
            m_cursor = std::size_t(it - m_samples.begin()) - 1;
            break;
        }
        ++m_cursor;
    }
    const DeviceSample& a = m_samples[m_cursor];
    if (seconds == a.time) {
        out = a;
        return out;
    }
    const DeviceSample& b = m_samples[m_cursor + 1];
    const double alpha = (seconds - a.time) / (b.time - a.time);
    out = a;
    out.time = seconds;
    out.position = a.position + alpha * (b.position - a.position);
    out.velocity = a.velocity + alpha * (b.velocity - a.velocity);
    out.pressure = a.pressure + alpha * (b.pressure - a.pressure);
    out.tiltX = a.tiltX + alpha * (b.tiltX - a.tiltX);
    out.tiltY = a.tiltY + alpha * (b.tiltY - a.tiltY);
    return out;  // buttons: those of the earlier sample
}

void TrajectoryDevice::sendForce(const Vec3& forceN) {
    m_lastForce = forceN;
    if (m_keepForces) m_sentForces.push_back(forceN);
}

void TrajectoryDevice::keepForces(bool keep, std::size_t expected) {
    m_keepForces = keep;
    m_sentForces.clear();
    m_sentForces.reserve(expected);
}

SampleSequenceDevice::SampleSequenceDevice(std::vector<DeviceSample> samples, DeviceInfo info)
    : m_samples(std::move(samples)), m_info(std::move(info)) {}

DeviceSample SampleSequenceDevice::read(double seconds) {
    if (m_samples.empty()) {
        DeviceSample sample;
        sample.time = seconds;
        return sample;
    }
    const DeviceSample& sample = m_samples[std::min(m_next, m_samples.size() - 1)];
    ++m_next;
    return sample;
}

void SampleSequenceDevice::sendForce(const Vec3&) {}

}  // namespace softtouch
